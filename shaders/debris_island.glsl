// isoterra — debris of a few samples: the debris filter's second pass
// (shaders/mc_debris_flood.comp) asks it; app/extract/mc_ref.c mirrors it
// (the CPU reference, which tests/test_debris.c checks by labelling).  box holds the inside bits of a 7x7x7
// box around a sample, row (dz + 3) * 7 + dy + 3 the samples dx = -3 .. 3
// in bits 0 .. 6 (a sample beyond the grid outside).
// The sample's 6-connected inside component, grown within the box, is
// debris when it never reaches the box's faces and spans at most
// DEBRIS_SPAN samples along each axis: then each of its samples finds the
// whole component within its own box, and all decide alike; a component
// that spans more is kept by every one of its samples.  At most 27
// samples, so 28 steps of growth settle it (one that still grows is more).
#define DEBRIS_SPAN 3
bool debris_island(uint box[49])
{
	uint cur[49];
	for (int i = 0; i < 49; i++)
		cur[i] = 0u;
	cur[24] = box[24] & 8u;
	if (cur[24] == 0u)
		return false; // an outside centre: no component
	bool settled = false;
	for (int step = 0; step < 28 && !settled; step++) {
		uint nxt[49];
		bool grew = false;
		for (int z = 0; z < 7; z++)
			for (int y = 0; y < 7; y++) {
				int i = z * 7 + y;
				uint v = cur[i] | (cur[i] << 1) | (cur[i] >> 1);
				if (y > 0)
					v |= cur[i - 1];
				if (y < 6)
					v |= cur[i + 1];
				if (z > 0)
					v |= cur[i - 7];
				if (z < 6)
					v |= cur[i + 7];
				v &= box[i];
				grew = grew || v != cur[i];
				nxt[i] = v;
			}
		for (int i = 0; i < 49; i++)
			cur[i] = nxt[i];
		settled = !grew;
		uint face = 0u; // a face reached: dx or dy or dz = +-3
		for (int k = 0; k < 7; k++)
			face |= cur[k] | cur[42 + k] | cur[k * 7] | cur[k * 7 + 6];
		for (int i = 0; i < 49; i++)
			face |= cur[i] & 0x41u;
		if (face != 0u)
			return false;
	}
	if (!settled)
		return false;
	uint xs = 0u;
	int ylo = 7, yhi = -1, zlo = 7, zhi = -1;
	for (int z = 0; z < 7; z++)
		for (int y = 0; y < 7; y++) {
			uint v = cur[z * 7 + y];
			xs |= v;
			if (v != 0u) {
				ylo = min(ylo, y);
				yhi = max(yhi, y);
				zlo = min(zlo, z);
				zhi = max(zhi, z);
			}
		}
	return findMSB(xs) - findLSB(xs) < DEBRIS_SPAN && yhi - ylo < DEBRIS_SPAN && zhi - zlo < DEBRIS_SPAN;
}
