// isoterra — on-screen display: one quad (triangle strip from gl_VertexID)
// covering the text box, in pixels of the target framebuffer.
uniform vec4 u_box; // x, y (from the top), width, height in pixels
uniform vec2 u_fb;  // framebuffer size in pixels

void main()
{
	vec2 c = vec2(float(gl_VertexID & 1), float(gl_VertexID >> 1));
	vec2 px = u_box.xy + c * u_box.zw;         // top-left origin
	vec2 ndc = vec2(px.x / u_fb.x * 2.0 - 1.0, 1.0 - px.y / u_fb.y * 2.0);
	gl_Position = vec4(ndc, 0.0, 1.0);
}
