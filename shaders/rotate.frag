// isoterra — the panel's rotation (--rotate): the finished frame (u_src,
// the picture upright) drawn onto an output turned u_quarter quarter turns
// clockwise, whose size is the picture's with its sides swapped for odd
// turns.  A turn moves whole pixels: each output pixel fetches its one
// texel by integer index (texelFetch), no filtering and no texture
// coordinates to round, so the output is the picture's pixels exactly on
// every driver (filtered taps at texel centres were not, under llvmpipe on
// QEMU's emulated CPU: tests/vm/test_kms.sh).
uniform highp sampler2D u_src;
uniform int u_quarter; // 0..3: 0, 90, 180, 270 degrees clockwise
out vec4 o_color;

void main()
{
	ivec2 o = ivec2(gl_FragCoord.xy); // bottom-up, as the texture's rows
	ivec2 n = textureSize(u_src, 0);
	ivec2 s = o;
	if (u_quarter == 1)
		s = ivec2(n.x - 1 - o.y, o.x);
	else if (u_quarter == 2)
		s = ivec2(n.x - 1 - o.x, n.y - 1 - o.y);
	else if (u_quarter == 3)
		s = ivec2(o.y, n.y - 1 - o.x);
	o_color = vec4(texelFetch(u_src, clamp(s, ivec2(0), n - 1), 0).rgb, 1.0);
}
