// isoterra — V4L2 output: the rendered RGBA frame -> the device's byte
// layout (packed/planar YCbCr, BT.601 or BT.709 limited range, or RGB24),
// with the device's bytesperline and sizeimage.  One invocation writes 4
// bytes of the frame: word i goes to texel (i % OUT_W, i / OUT_W) of an
// RGBA8 image that glReadPixels copies, byte for byte, into a pixel buffer.
//
// The host (hal/convert.c) compiles one program per format: it defines
// CONV_WG_SIZE, the F_* format names (from its enum conv_fmt's table) and FMT,
// one of them, so the per-byte format switch below is resolved at compile time.  The common
// case of packed 4:2:2 with 4-byte aligned lines (a word = one macropixel:
// two texel fetches) has its own path.
#if !defined(FMT) || !defined(CONV_WG_SIZE) || !defined(F_YUYV) || !defined(F_BGR24)
#error "FMT, CONV_WG_SIZE and the F_* formats must be defined by the host (hal/convert.c)"
#endif
layout(local_size_x = CONV_WG_SIZE) in;
precision highp image2D;

layout(binding = TEX_FRAME) uniform highp sampler2D u_src; // the rendered frame (GL rows: bottom first)
layout(rgba8, binding = IMG_CONVERT_OUT) writeonly uniform highp image2D u_out;
uniform uint u_w, u_h, u_bpl, u_size, u_words, u_out_w; // the device's frame
uniform bool u_scaled;           // the device's size differs from the frame's
uniform vec2 u_k;                // (Kr, Kb)

// pixel (x, y) of the device's frame, y from the top; clamped to the edge.
// Same size: the rendered pixel itself; else bilinear from the rendered frame.
vec3 rgb(uint x, uint y)
{
	x = min(x, u_w - 1u);
	y = min(y, u_h - 1u);
	if (u_scaled) {
		vec2 uv = vec2((float(x) + 0.5) / float(u_w), 1.0 - (float(y) + 0.5) / float(u_h));
		return textureLod(u_src, uv, 0.0).rgb;
	}
	return texelFetch(u_src, ivec2(int(x), int(u_h - 1u - y)), 0).rgb;
}

float luma(vec3 c) { return dot(c, vec3(u_k.x, 1.0 - u_k.x - u_k.y, u_k.y)); }
uint q(float v) { return uint(clamp(floor(v + 0.5), 0.0, 255.0)); }
uint Y(vec3 c) { return q(16.0 + 219.0 * luma(c)); }
uint Cb(vec3 c) { return q(128.0 + 112.0 * (c.b - luma(c)) / (1.0 - u_k.y)); }
uint Cr(vec3 c) { return q(128.0 + 112.0 * (c.r - luma(c)) / (1.0 - u_k.x)); }

vec3 avg4(uint x, uint y)
{
	return 0.25 * (rgb(x, y) + rgb(x + 1u, y) + rgb(x, y + 1u) + rgb(x + 1u, y + 1u));
}

uint byte_at(uint off)
{
	if (off >= u_size)
		return 0u;
	if (FMT == F_YUYV || FMT == F_UYVY) {
		uint y = off / u_bpl, x = off % u_bpl;
		if (y >= u_h || x >= 4u * ((u_w + 1u) / 2u))
			return 0u;
		uint px = (x / 4u) * 2u, k = x % 4u;
		if (FMT == F_UYVY)
			k ^= 1u; // U Y0 V Y1 -> the roles of Y0 U Y1 V
		if (k == 0u)
			return Y(rgb(px, y));
		if (k == 2u)
			return Y(rgb(px + 1u, y));
		vec3 c = 0.5 * (rgb(px, y) + rgb(px + 1u, y));
		return k == 1u ? Cb(c) : Cr(c);
	}
	if (FMT == F_RGB24 || FMT == F_BGR24) {
		uint y = off / u_bpl, x = off % u_bpl;
		if (y >= u_h || x >= 3u * u_w)
			return 0u;
		uint k = x % 3u;
		if (FMT == F_BGR24)
			k = 2u - k;
		vec3 c = rgb(x / 3u, y);
		return q(255.0 * (k == 0u ? c.r : k == 1u ? c.g : c.b));
	}
	// planar 4:2:0
	uint luma_size = u_bpl * u_h;
	if (off < luma_size) {
		uint y = off / u_bpl, x = off % u_bpl;
		return x < u_w ? Y(rgb(x, y)) : 0u;
	}
	uint o = off - luma_size, cw = (u_w + 1u) / 2u, ch = (u_h + 1u) / 2u;
	if (FMT == F_NV12 || FMT == F_NV21) {
		uint y = o / u_bpl, x = o % u_bpl;
		if (y >= ch || x >= 2u * cw)
			return 0u;
		uint k = x % 2u;
		if (FMT == F_NV21)
			k ^= 1u;
		vec3 c = avg4((x / 2u) * 2u, 2u * y);
		return k == 0u ? Cb(c) : Cr(c);
	}
	// YU12: Y plane, then U, then V, each chroma row bytesperline / 2
	uint cbpl = u_bpl / 2u, plane = cbpl * ch;
	bool v = o >= plane;
	if (v)
		o -= plane;
	uint y = o / cbpl, x = o % cbpl;
	if (y >= ch || x >= cw)
		return 0u;
	vec3 c = avg4(2u * x, 2u * y);
	return v ? Cr(c) : Cb(c);
}

// 4:2:2 with 4-byte aligned lines: word i is one whole macropixel (two
// pixels) or line padding; (0, 0, 0, 0) past the last one
uvec4 macropixel(uint i)
{
	uint wpl = u_bpl / 4u, y = i / wpl, px = 2u * (i % wpl);
	if (y >= u_h || px >= u_w || 4u * i >= u_size)
		return uvec4(0u);
	vec3 a = rgb(px, y), b = rgb(px + 1u, y), c = 0.5 * (a + b);
	uvec4 w = uvec4(Y(a), Cb(c), Y(b), Cr(c));
	return FMT == F_UYVY ? w.yxwz : w;
}

void main()
{
	uint i = gl_GlobalInvocationID.x;
	if (i >= u_words)
		return;
	uvec4 w;
	if ((FMT == F_YUYV || FMT == F_UYVY) && u_bpl % 4u == 0u) {
		w = macropixel(i);
	} else {
		uint o = 4u * i;
		w = uvec4(byte_at(o), byte_at(o + 1u), byte_at(o + 2u), byte_at(o + 3u));
	}
	imageStore(u_out, ivec2(int(i % u_out_w), int(i / u_out_w)), vec4(w) / 255.0);
}
