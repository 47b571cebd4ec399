// isoterra — the governor's upscale: the frame drawn at a lower resolution
// (the lower-left src_px texels of u_src) brought to the target's size with
// a Catmull-Rom bicubic (five bilinear taps), clamped to the range of the
// four nearest texels so edges stay crisp without bicubic halos.
uniform highp sampler2D u_src;
uniform vec2 u_src_px; // the low-resolution frame's size in texels
uniform vec2 u_tex_px; // the texture's size
in vec2 v_uv;
out vec4 o_color;

vec3 tap(vec2 texel) // bilinear, kept inside the drawn rectangle
{
	return texture(u_src, clamp(texel, vec2(0.5), u_src_px - 0.5) / u_tex_px).rgb;
}

void main()
{
	vec2 pos = v_uv * u_src_px;
	vec2 tc = floor(pos - 0.5) + 0.5; // centre of the texel left/below
	vec2 f = pos - tc;
	vec2 w0 = f * (-0.5 + f * (1.0 - 0.5 * f));
	vec2 w1 = 1.0 + f * f * (-2.5 + 1.5 * f);
	vec2 w2 = f * (0.5 + f * (2.0 - 1.5 * f));
	vec2 w3 = f * f * (-0.5 + 0.5 * f);
	vec2 w12 = w1 + w2;
	vec2 t12 = tc + w2 / w12;
	vec2 t0 = tc - 1.0, t3 = tc + 2.0;
	vec3 c = tap(vec2(t12.x, t0.y)) * (w12.x * w0.y) + tap(vec2(t0.x, t12.y)) * (w0.x * w12.y) +
		 tap(t12) * (w12.x * w12.y) + tap(vec2(t3.x, t12.y)) * (w3.x * w12.y) +
		 tap(vec2(t12.x, t3.y)) * (w12.x * w3.y);
	float wsum = w12.x * w0.y + w0.x * w12.y + w12.x * w12.y + w3.x * w12.y + w12.x * w3.y;
	c /= wsum;
	ivec2 i = ivec2(tc - 0.5), hi = ivec2(u_src_px) - 1;
	vec3 a = texelFetch(u_src, clamp(i, ivec2(0), hi), 0).rgb;
	vec3 b = texelFetch(u_src, clamp(i + ivec2(1, 0), ivec2(0), hi), 0).rgb;
	vec3 d = texelFetch(u_src, clamp(i + ivec2(0, 1), ivec2(0), hi), 0).rgb;
	vec3 e = texelFetch(u_src, clamp(i + ivec2(1, 1), ivec2(0), hi), 0).rgb;
	o_color = vec4(clamp(c, min(min(a, b), min(d, e)), max(max(a, b), max(d, e))), 1.0);
}
