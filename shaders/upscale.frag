// isoterra — the governor's upscale: the frame drawn at a lower resolution
// (the lower-left src_px texels of u_src) brought to the target's size by
// "sharp bilinear": one bilinear tap whose position inside the texel is
// pushed towards the texel's centre, so the blend between two texels spans
// 1.5 output pixels whatever the scale (plain bilinear: 1 / scale, two
// pixels at half scale; nearest: none, and stairs).  Edges stay crisper than
// bilinear's, nothing rings (every pixel lies between its four nearest
// texels), and the pass costs one texture tap a pixel: on a software
// rasterizer the bicubic it replaces (nine taps) over a 1280x720 target
// cost about a third of the frame that the lower scale was meant to save.
uniform highp sampler2D u_src;
uniform vec2 u_src_px; // the low-resolution frame's size in texels
uniform vec2 u_tex_px; // the texture's size
in vec2 v_uv;
out vec4 o_color;

void main()
{
	vec2 pos = v_uv * u_src_px;     // in source texels
	vec2 tc = floor(pos - 0.5) + 0.5; // centre of the texel left/below
	vec2 f = pos - tc;                // 0..1 towards the next texel
	// output pixels per source texel, over the blend's 1.5 pixels
	float k = max(u_tex_px.x / u_src_px.x * (2.0 / 3.0), 1.0);
	f = clamp((f - 0.5) * k + 0.5, 0.0, 1.0);
	vec2 p = clamp(tc + f, vec2(0.5), u_src_px - 0.5);
	o_color = vec4(texture(u_src, p / u_tex_px).rgb, 1.0);
}
