// isoterra — debris of a few samples: the debris filter's second pass
// (shaders/mc_debris_flood.comp) asks it; app/extract/mc_ref.c mirrors it
// (the CPU reference, which tests/test_debris.c checks by labelling).  The
// box: the inside bits of DEBRIS_BOX samples an edge around a sample
// (abi.h: 2 * DEBRIS_SPAN + 1), row (dz + S) * B + dy + S the samples
// dx = -S .. S in bits 0 .. B - 1 (S = DEBRIS_SPAN, B = DEBRIS_BOX; a
// sample beyond the grid outside).
// The sample's 6-connected inside component, grown within the box, is
// debris when it never reaches the box's faces and spans at most S samples
// along each axis: then each of its samples finds the whole component
// within its own box (the others lie within S - 1 steps along each axis),
// and all decide alike; a component that spans more is kept by every one
// of its samples (it reaches the faces, or its span shows).  The growth
// runs in place, row after row (a fixed point, whatever the order): a
// component of at most S^3 samples settles within S^3 + 1 sweeps, one
// that still grows is larger.
// The box's rows are read as the growth first reaches them (the
// including pass defines debris_box_row(dz, dy), dz, dy = 0 .. B - 1: the
// inside samples that are candidates of the first pass in bits 0 .. B - 1,
// those that are not in bits 16 ..).  Every sample of debris is a
// candidate, so the growth stops, kept, when it reaches one that is not
// (a component of the ground reaches its rock within a step or two).
#define DEBRIS_ROWS (DEBRIS_BOX * DEBRIS_BOX)
bool debris_island()
{
	const int B = DEBRIS_BOX, S = DEBRIS_SPAN;
	const uint faces = 1u | (1u << uint(B - 1));
	uint cur[DEBRIS_ROWS], box[DEBRIS_ROWS];
	for (int i = 0; i < DEBRIS_ROWS; i++) {
		cur[i] = 0u;
		box[i] = ~0u; // not read yet
	}
	int centre = S * B + S;
	box[centre] = debris_box_row(S, S);
	cur[centre] = box[centre] & (1u << uint(S));
	if (cur[centre] == 0u)
		return false; // an outside centre: no component
	bool settled = false;
	int zlo = S, zhi = S, ylo = S, yhi = S; // the rows the component has reached
	for (int sweep = 0; sweep <= S * S * S && !settled; sweep++) {
		bool grew = false;
		uint face = 0u;
		for (int z = max(zlo - 1, 0); z <= min(zhi + 1, B - 1); z++)
			for (int y = max(ylo - 1, 0); y <= min(yhi + 1, B - 1); y++) {
				int i = z * B + y;
				uint v = cur[i] | (cur[i] << 1) | (cur[i] >> 1);
				if (y > 0)
					v |= cur[i - 1];
				if (y < B - 1)
					v |= cur[i + 1];
				if (z > 0)
					v |= cur[i - B];
				if (z < B - 1)
					v |= cur[i + B];
				if (v == 0u)
					continue; // nothing reaches this row yet
				if (box[i] == ~0u)
					box[i] = debris_box_row(z, y);
				if ((v & (box[i] >> 16u)) != 0u)
					return false; // an inside sample that is no candidate: more than debris
				v &= box[i] & 0xFFFFu;
				if (v != cur[i]) {
					grew = true;
					cur[i] = v;
					zlo = min(zlo, z);
					zhi = max(zhi, z);
					ylo = min(ylo, y);
					yhi = max(yhi, y);
				}
				face |= v & faces;
			}
		settled = !grew;
		if (face != 0u || zlo == 0 || zhi == B - 1 || ylo == 0 || yhi == B - 1)
			return false; // a face reached: more than S samples along an axis
	}
	if (!settled)
		return false;
	uint xs = 0u;
	for (int z = zlo; z <= zhi; z++)
		for (int y = ylo; y <= yhi; y++)
			xs |= cur[z * B + y];
	return findMSB(xs) - findLSB(xs) < S && yhi - ylo < S && zhi - zlo < S;
}
