// isoterra — the panel's rotation (--rotate): the finished frame (u_src,
// the picture upright) drawn onto an output turned u_quarter quarter turns
// clockwise; the output and the picture have their sizes swapped for odd
// turns, so every output pixel's centre lands on a texel's centre.
uniform highp sampler2D u_src;
uniform int u_quarter; // 0..3: 0, 90, 180, 270 degrees clockwise
in vec2 v_uv;          // 0 .. 1 over the output, bottom-up
out vec4 o_color;

void main()
{
	vec2 s = v_uv;
	if (u_quarter == 1)
		s = vec2(1.0 - v_uv.y, v_uv.x);
	else if (u_quarter == 2)
		s = vec2(1.0 - v_uv.x, 1.0 - v_uv.y);
	else if (u_quarter == 3)
		s = vec2(v_uv.y, 1.0 - v_uv.x);
	o_color = vec4(texture(u_src, s).rgb, 1.0);
}
