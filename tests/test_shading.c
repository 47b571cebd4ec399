/* isoterra tests — the shading's light and air (shaders/shade.glsl) on the
 * GPU, through shaders/shade_test.comp:
 *   - the fog: the amount the shader's closed form gives for a ray, against
 *     the CPU's numerical integral (Simpson, 400 intervals) of the same
 *     height-dependent density along it, 1 - exp(-optical depth); and the
 *     haze's colour: the horizon's away from the sun, warmer towards it;
 *   - the snow: its invariants (none on steep ground, none well under the
 *     line, full cover on flat ground well over it, more the higher and
 *     the flatter) over a grid of altitudes, slopes and both noises;
 *   - the gamma fits (albedo_to_linear, linear_to_srgb) against powf, in
 *     levels of 255 of the picture written.
 * The sun shadows have their own test against the CPU (test_shadows.c). */
#include "app.h"
#include "tcheck.h"
#include "gpu_fixture.h"

#include <math.h>
#include <string.h>

static bool run(GLuint prog, int mode, const float *in, size_t in_vec4, uint32_t n, float density, float *out)
{
	GLuint buf[2];
	glGenBuffers(2, buf);
	glBindBuffer(GL_SHADER_STORAGE_BUFFER, buf[0]);
	glBufferData(GL_SHADER_STORAGE_BUFFER, (GLsizeiptr)(in_vec4 * 16), in, GL_STATIC_DRAW);
	glBindBuffer(GL_SHADER_STORAGE_BUFFER, buf[1]);
	glBufferData(GL_SHADER_STORAGE_BUFFER, (GLsizeiptr)n * 16, NULL, GL_STATIC_DRAW);
	glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_AUX_IN, buf[0]);
	glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_AUX_OUT, buf[1]);
	glUseProgram(prog);
	glUniform1i(gpu_uniform(prog, "u_mode"), mode);
	glUniform1ui(gpu_uniform(prog, "u_n"), n);
	glUniform1f(gpu_uniform(prog, "u_density"), density);
	glDispatchCompute((n + WG_SIZE - 1) / WG_SIZE, 1, 1);
	glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
	int rc = gpu_read_buffer(buf[1], 0, (GLsizeiptr)n * 16, out);
	glDeleteBuffers(2, buf);
	return rc == 0 && gpu_check("shade_test") == 0;
}

static uint32_t rng = 2024;
static float uni(float lo, float hi)
{
	rng = rng * 1664525u + 1013904223u;
	return lo + (hi - lo) * (float)(rng >> 8) / (float)(1u << 24);
}

/* 1 - exp(-optical depth) of the ray eye -> pos: density * fog *
 * exp(-b * y) integrated numerically, y from the eye's height (at least
 * -50, as the shader clamps it) along the ray. */
static double fog_ref(const struct params *p, const float eye[3], const float pos[3], double density)
{
	double d[3] = { pos[0] - eye[0], pos[1] - eye[1], pos[2] - eye[2] };
	double dist = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]), y0 = fmax(eye[1], -50.0), b = p->fog_height;
	int n = 400;
	double s = 0.0;
	for (int i = 0; i <= n; i++) {
		double u = (double)i / n, w = (i == 0 || i == n) ? 1 : (i & 1) ? 4 : 2;
		s += w * exp(-b * (y0 + u * d[1]));
	}
	double tau = density * p->fog * dist * s / (3.0 * n);
	return 1.0 - exp(-fmin(tau, 50.0));
}

static void check_fog(GLuint prog, struct params *p, float fog_height)
{
	p->fog_height = fog_height;
	gpu_set_param_uniforms(prog, p);
	enum { N = 2048 };
	static float in[2 * N * 4], out[N * 4];
	float density = 0.35f / 36.0f; /* the world's: 0.35 / (0.6 view distance) */
	for (int i = 0; i < N; i++) {
		float *e = in + 8 * i, *q = e + 4;
		e[0] = uni(-50, 50), e[1] = uni(-30, 40), e[2] = uni(-50, 50), e[3] = 1;
		float r = uni(0.5f, 150.0f), az = uni(0, 6.2832f), el = uni(-1.2f, 0.6f);
		q[0] = e[0] + r * cosf(el) * cosf(az), q[1] = e[1] + r * sinf(el), q[2] = e[2] + r * cosf(el) * sinf(az);
		q[3] = 1;
	}
	CHECK(run(prog, 0, in, 2 * N, N, density, out), "fog: dispatch");
	double worst = 0.0, mean = 0.0;
	for (int i = 0; i < N; i++) {
		double ref = fog_ref(p, in + 8 * i, in + 8 * i + 4, density), err = fabs(out[4 * i] - ref);
		worst = fmax(worst, err);
		mean += ref / N;
	}
	printf("fog, fog_height %.2f: %d rays, mean amount %.3f, GPU vs CPU integral: worst %.2g\n", (double)fog_height,
	       N, mean, worst);
	CHECK(worst <= 2e-3, "fog_height %.2f: the fog amount is off by %.3g", (double)fog_height, worst);
	CHECK(mean > 0.05 && mean < 0.95, "fog_height %.2f: the rays test little (mean amount %.3f)", (double)fog_height,
	      mean);
}

static void check_haze(GLuint prog, struct params *p)
{
	/* towards the sun, across it, away from it: a ray of 100 units, level */
	gpu_set_param_uniforms(prog, p);
	float el = p->light_el * (float)M_PI / 180.0f, az = p->light_az * (float)M_PI / 180.0f;
	float sun[3] = { cosf(el) * cosf(az), sinf(el), cosf(el) * sinf(az) };
	glProgramUniform3f(prog, gpu_uniform(prog, "u_sun_dir"), sun[0], sun[1], sun[2]);
	float in[3 * 8] = { 0 }, out[3 * 4];
	float dirs[3][2] = { { cosf(az), sinf(az) }, { -sinf(az), cosf(az) }, { -cosf(az), -sinf(az) } };
	for (int i = 0; i < 3; i++) {
		in[8 * i + 1] = 10.0f;
		in[8 * i + 4] = 100.0f * dirs[i][0];
		in[8 * i + 5] = 10.0f;
		in[8 * i + 6] = 100.0f * dirs[i][1];
	}
	CHECK(run(prog, 0, in, 6, 3, 0.01f, out), "haze: dispatch");
	float horizon[3] = { powf(0.62f, 2.2f), powf(0.74f, 2.2f), powf(0.88f, 2.2f) };
	for (int c = 0; c < 3; c++)
		CHECK(fabsf(out[8 + 1 + c] - horizon[c]) < 1e-4f, "away from the sun the haze is the horizon's colour (%d)",
		      c);
	float warm_to = out[1] - out[3], warm_across = out[4 + 1] - out[4 + 3], warm_away = out[8 + 1] - out[8 + 3];
	printf("haze red - blue: towards the sun %.3f, across %.3f, away %.3f\n", warm_to, warm_across, warm_away);
	CHECK(warm_to > warm_across + 0.05f && warm_across >= warm_away - 1e-5f, "the haze is warmer towards the sun");
}

static void check_snow(GLuint prog, struct params *p)
{
	gpu_set_param_uniforms(prog, p);
	/* alt - snow_line -6 .. 12 by 0.25 (73), up_n 0 .. 1 by 0.02 (51),
	 * slow and hgt 0 .. 1 by 0.25 (5 each) */
	enum { NA = 73, NU = 51, NS = 5, N = NA * NU * NS * NS };
	static float in[N * 4], out[N * 4];
	for (int a = 0, i = 0; a < NA; a++)
		for (int u = 0; u < NU; u++)
			for (int s = 0; s < NS; s++)
				for (int h = 0; h < NS; h++, i++) {
					in[4 * i] = p->snow_line - 6.0f + 0.25f * (float)a;
					in[4 * i + 1] = 0.02f * (float)u;
					in[4 * i + 2] = 0.25f * (float)s;
					in[4 * i + 3] = 0.25f * (float)h;
				}
	CHECK(run(prog, 1, in, N, N, 0.0f, out), "snow: dispatch");
	unsigned steep = 0, under = 0, bare = 0, down_alt = 0, down_up = 0, full = 0, partial = 0;
#define AT(a, u, s, h) out[4 * ((((a) * NU + (u)) * NS + (s)) * NS + (h))]
	for (int a = 0; a < NA; a++)
		for (int u = 0; u < NU; u++)
			for (int s = 0; s < NS; s++)
				for (int h = 0; h < NS; h++) {
					float v = AT(a, u, s, h), over = -6.0f + 0.25f * (float)a, up_n = 0.02f * (float)u;
					steep += up_n <= 0.5f && v != 0.0f;
					under += over <= -2.2f && v != 0.0f;
					bare += up_n >= 0.92f && over >= 2.2f && v < 0.999f;
					if (a > 0)
						down_alt += v < AT(a - 1, u, s, h) - 1e-6f;
					if (u > 0)
						down_up += v < AT(a, u - 1, s, h) - 1e-6f;
					full += v >= 0.999f;
					partial += v > 0.001f && v < 0.999f;
				}
#undef AT
	printf("snow: %d inputs, %u fully covered, %u partly (the frayed edge)\n", (int)N, full, partial);
	CHECK(steep == 0, "snow on ground steeper than up_n 0.5 (%u inputs)", steep);
	CHECK(under == 0, "snow 2.2 units under the snow line (%u inputs)", under);
	CHECK(bare == 0, "flat ground 2.2 units over the line not fully covered (%u inputs)", bare);
	CHECK(down_alt == 0, "less snow higher up (%u inputs)", down_alt);
	CHECK(down_up == 0, "less snow on flatter ground (%u inputs)", down_up);
	CHECK(full > N / 10 && partial > N / 50, "the grid tests little (%u full, %u partial)", full, partial);
}

/* The fits of gamma 2.2 against powf, over their ranges (the albedo up to
 * 1.3: the texture's grain brightens it; the display 0 .. 1, after the
 * tone mapping's clamp), in levels of 255 of what is written: the albedo's
 * error taken back through pow 1/2.2 (what a viewer sees of it). */
static void check_gamma(GLuint prog)
{
	enum { N = 2601 };
	static float in[N * 4], out[N * 4];
	for (int i = 0; i < N; i++) {
		float x = (float)i / (N - 1);
		in[4 * i + 0] = x;          /* display's input, and an albedo 0 .. 1 */
		in[4 * i + 1] = 1.3f * x;   /* an albedo up to 1.3 */
		in[4 * i + 2] = 0.5f * x;
	}
	CHECK(run(prog, 2, in, N, N, 0.0f, out), "gamma: dispatch");
	double worst_alb = 0, worst_disp = 0;
	for (int i = 0; i < N; i++) {
		for (int c = 0; c < 3; c++) {
			double a = in[4 * i + c], lin = out[4 * i + c];
			double back = pow(lin > 0 ? lin : 0, 1 / 2.2);
			worst_alb = fmax(worst_alb, fabs(back - a) * 255);
			CHECK(lin >= -1e-6, "albedo_to_linear(%g) = %g is negative", a, lin);
		}
		double x = in[4 * i];
		worst_disp = fmax(worst_disp, fabs(out[4 * i + 3] - pow(x, 1 / 2.2)) * 255);
	}
	printf("gamma fits: albedo within %.2f, display within %.2f levels of 255\n", worst_alb, worst_disp);
	CHECK(worst_alb <= 1.25, "albedo_to_linear: %.2f levels off pow 2.2 (1.25 allowed)", worst_alb);
	CHECK(worst_disp <= 0.6, "linear_to_srgb: %.2f levels off pow 1/2.2 (0.6 allowed)", worst_disp);
	/* both rise: no band where a brighter input writes a darker pixel */
	unsigned falls = 0;
	for (int i = 1; i < N; i++)
		falls += out[4 * i + 1] < out[4 * (i - 1) + 1] || out[4 * i + 3] < out[4 * (i - 1) + 3];
	CHECK(falls == 0, "a gamma fit falls somewhere (%u steps)", falls);
}

int main(void)
{
	struct platform *plat = fixture_open();
	char err[512] = "";
	GLuint prog = gpu_compute_program("shade_test.comp", NULL, err, sizeof(err));
	CHECK(prog != 0, "shade_test.comp: %s", err);
	if (prog) {
		struct params p;
		params_defaults(&p);
		check_haze(prog, &p);
		check_fog(prog, &p, p.fog_height);
		check_fog(prog, &p, 0.0f);
		check_fog(prog, &p, 0.25f);
		check_snow(prog, &p);
		check_gamma(prog);
		glDeleteProgram(prog);
	}
	platform_close(plat);
	return tc_done("shading");
}
