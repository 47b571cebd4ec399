// isoterra — the attract playlist's crossfade (app/kiosk.c through
// renderer_fade_kept): the last show's kept frame over the new show's,
// weighted by u_alpha (1 at the change, 0 at the fade's end).
uniform highp sampler2D u_src;
uniform float u_alpha;
in vec2 v_uv;
out vec4 o_color;

void main()
{
	o_color = vec4(texture(u_src, v_uv).rgb, u_alpha);
}
