// isoterra — V4L2 output: the rendered RGBA frame -> the device's byte
// layout (packed/planar YCbCr, BT.601 or BT.709 limited range, or RGB24),
// with the device's bytesperline and sizeimage.  One invocation writes 4
// bytes of the frame: word i goes to texel (i % OUT_W, i / OUT_W) of an
// RGBA8 image that glReadPixels copies, byte for byte, into a pixel buffer.
layout(local_size_x = 64) in;
precision highp image2D;

#define F_YUYV 0u
#define F_UYVY 1u
#define F_NV12 2u
#define F_NV21 3u
#define F_YU12 4u
#define F_RGB24 5u
#define F_BGR24 6u

uniform highp sampler2D u_src;   // the rendered frame (GL rows: bottom first)
layout(rgba8, binding = 0) writeonly uniform highp image2D u_out;
uniform uint u_fmt, u_w, u_h, u_bpl, u_size, u_words, u_out_w;
uniform vec2 u_k;                // (Kr, Kb)

vec3 rgb(uint x, uint y)
{
	x = min(x, u_w - 1u);
	y = min(y, u_h - 1u);
	vec2 uv = vec2((float(x) + 0.5) / float(u_w), 1.0 - (float(y) + 0.5) / float(u_h));
	return texture(u_src, uv).rgb;
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
	if (u_fmt == F_YUYV || u_fmt == F_UYVY) {
		uint y = off / u_bpl, x = off % u_bpl;
		if (y >= u_h || x >= 4u * ((u_w + 1u) / 2u))
			return 0u;
		uint px = (x / 4u) * 2u, k = x % 4u;
		if (u_fmt == F_UYVY)
			k ^= 1u; // U Y0 V Y1 -> the roles of Y0 U Y1 V
		if (k == 0u)
			return Y(rgb(px, y));
		if (k == 2u)
			return Y(rgb(px + 1u, y));
		vec3 c = 0.5 * (rgb(px, y) + rgb(px + 1u, y));
		return k == 1u ? Cb(c) : Cr(c);
	}
	if (u_fmt == F_RGB24 || u_fmt == F_BGR24) {
		uint y = off / u_bpl, x = off % u_bpl;
		if (y >= u_h || x >= 3u * u_w)
			return 0u;
		uint k = x % 3u;
		if (u_fmt == F_BGR24)
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
	if (u_fmt == F_NV12 || u_fmt == F_NV21) {
		uint y = o / u_bpl, x = o % u_bpl;
		if (y >= ch || x >= 2u * cw)
			return 0u;
		uint k = x % 2u;
		if (u_fmt == F_NV21)
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

void main()
{
	uint i = gl_GlobalInvocationID.x;
	if (i >= u_words)
		return;
	uint o = 4u * i;
	vec4 b = vec4(float(byte_at(o)), float(byte_at(o + 1u)), float(byte_at(o + 2u)), float(byte_at(o + 3u))) / 255.0;
	imageStore(u_out, ivec2(int(i % u_out_w), int(i / u_out_w)), b);
}
