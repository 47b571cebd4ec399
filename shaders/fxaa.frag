// isoterra — edge smoothing over the finished frame (--antialias fxaa; the
// idea of Lottes' FXAA, in its small form): where the luma of a pixel and
// its four diagonal neighbours spans more than a threshold, the local
// gradient gives the edge's direction, and two or four bilinear taps along
// it replace the pixel (the four only while they stay inside the
// neighbourhood's luma range, so no new halo appears).  Flat regions keep
// their pixel.  Reads the frame copied into u_src (upscale.c).
uniform highp sampler2D u_src;
uniform vec2 u_src_px; // the frame's size in texels (the lower-left part of u_src)
uniform vec2 u_tex_px; // the texture's size
in vec2 v_uv;
out vec4 o_color;

float luma(vec3 c) { return dot(c, vec3(0.299, 0.587, 0.114)); }

vec3 tap(vec2 uv) { return texture(u_src, uv).rgb; }

void main()
{
	ivec2 p = ivec2(v_uv * u_src_px);
	ivec2 hi = ivec2(u_src_px) - 1;
	vec3 m = texelFetch(u_src, p, 0).rgb;
	float lm = luma(m);
	float lnw = luma(texelFetch(u_src, clamp(p + ivec2(-1, 1), ivec2(0), hi), 0).rgb);
	float lne = luma(texelFetch(u_src, clamp(p + ivec2(1, 1), ivec2(0), hi), 0).rgb);
	float lsw = luma(texelFetch(u_src, clamp(p + ivec2(-1, -1), ivec2(0), hi), 0).rgb);
	float lse = luma(texelFetch(u_src, clamp(p + ivec2(1, -1), ivec2(0), hi), 0).rgb);
	float lo = min(lm, min(min(lnw, lne), min(lsw, lse)));
	float up = max(lm, max(max(lnw, lne), max(lsw, lse)));
	if (up - lo < max(1.0 / 32.0, up * 0.125)) { // no edge here
		o_color = vec4(m, 1.0);
		return;
	}
	// across the edge: the gradient of the diagonal lumas; along it: its normal
	vec2 dir = vec2(-((lnw + lne) - (lsw + lse)), (lnw + lsw) - (lne + lse));
	float reduce = max((lnw + lne + lsw + lse) * (0.25 / 8.0), 1.0 / 128.0);
	dir = clamp(dir / (min(abs(dir.x), abs(dir.y)) + reduce), -8.0, 8.0) / u_tex_px;
	vec2 uv = (vec2(p) + 0.5) / u_tex_px;
	vec3 a = 0.5 * (tap(uv - dir / 6.0) + tap(uv + dir / 6.0));
	vec3 b = 0.5 * a + 0.25 * (tap(uv - dir * 0.5) + tap(uv + dir * 0.5));
	float lb = luma(b);
	o_color = vec4(lb < lo || lb > up ? a : b, 1.0);
}
