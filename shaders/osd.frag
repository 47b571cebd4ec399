// isoterra — on-screen display: text rows from an embedded bitmap font
// (texture: one 6x8 cell per printable ASCII character), a value bar, on a
// translucent dark box.
precision highp usampler2D;

#define OSD_COLS 40
#define OSD_ROWS 2
uniform highp usampler2D u_font; // R8UI, FONT_COUNT*6 x 8, 0 or 1
uniform uint u_text[OSD_COLS * OSD_ROWS];
uniform vec4 u_box;
uniform vec2 u_fb;
uniform float u_scale;   // framebuffer pixels per font pixel
uniform float u_bar;     // 0..1 value position, < 0 = no bar
uniform float u_alpha;   // fade
out vec4 frag;

void main()
{
	vec2 p = vec2(gl_FragCoord.x, u_fb.y - gl_FragCoord.y) - u_box.xy; // box pixels, top-left origin
	vec2 f = floor(p / u_scale) - vec2(4.0, 3.0);                      // font pixels inside the margin
	vec4 bg = vec4(0.05, 0.06, 0.08, 0.72);
	vec4 col = bg;
	int cx = int(floor(f.x / 6.0)), cy = int(floor(f.y / 10.0));
	if (f.x >= 0.0 && f.y >= 0.0 && cx < OSD_COLS && cy < OSD_ROWS) {
		int gx = int(f.x) - cx * 6, gy = int(f.y) - cy * 10;
		uint ch = u_text[cy * OSD_COLS + cx];
		if (gy < 8 && ch >= 32u && ch < 127u) {
			uint on = texelFetch(u_font, ivec2(int(ch - 32u) * 6 + gx, gy), 0).r;
			if (on != 0u)
				col = cy == 0 ? vec4(1.0, 0.86, 0.35, 1.0) : vec4(1.0);
		}
	}
	// value bar below the text rows
	float by = f.y - float(OSD_ROWS * 10);
	float bw = u_box.z / u_scale - 8.0;
	if (u_bar >= 0.0 && by >= 0.0 && by < 3.0 && f.x >= 0.0 && f.x < bw)
		col = f.x < u_bar * bw ? vec4(0.35, 0.8, 1.0, 1.0) : vec4(0.3, 0.3, 0.35, 1.0);
	frag = vec4(col.rgb, col.a * u_alpha);
}
