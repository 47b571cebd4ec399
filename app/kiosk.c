/* isoterra — SIGHUP reload and the attract playlist (see kiosk.h). */
#include "kiosk.h"
#include "core.h"
#include "render.h"
#include "params.h"

#include <stdlib.h>
#include <string.h>

#define MAX_SHOWS 32

struct show {
	char name[PARAM_STR_MAX]; /* a preset, or a config file */
	bool file;
	double seconds;
};

struct kiosk {
	int argc;
	char **argv;
	struct params base;       /* the configuration as last read (start or reload) */
	struct show shows[MAX_SHOWS];
	int nshows;
	int cur;                  /* the show on screen, -1 before the first */
	long cycle;               /* completed passes through the playlist */
	double show_end;          /* run time (s) the current show ends */
	double show_start;        /* ... and began: its flight starts there */
	bool started;
	/* the crossfade from the last frame of the show before (kept by the renderer) */
	double fade_start, fade_s;
	bool fading;
	const struct renderer *fade_r; /* the renderer that kept it */
	double alpha;             /* the last show's weight this frame */
};

/* ---- the playlist ------------------------------------------------------- */

/* The show's parameters: the running configuration (the command line and
 * its --config), its preset or file over it, the seed + cycle. */
static int show_params(const struct show *s, const struct params *base, long cycle, struct params *q, char *err,
		       size_t errlen)
{
	*q = *base;
	int rc = s->file ? params_load_config_file(q, s->name, err, errlen)
			 : params_apply_preset(q, s->name, err, errlen);
	if (rc < 0)
		return -1;
	q->seed = (int)(((long)q->seed + cycle) % 2147483647L);
	return 0;
}

static int parse_playlist(struct kiosk *k, const char *text, char *err, size_t errlen)
{
	k->nshows = 0;
	char buf[PARAM_STR_MAX];
	snprintf(buf, sizeof(buf), "%s", text);
	char *save = NULL;
	for (char *tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
		char *e = str_trim(tok);
		if (!*e)
			continue;
		char *colon = strrchr(e, ':');
		char *end = NULL;
		double sec = colon ? strtod(colon + 1, &end) : 0;
		if (!colon || end == colon + 1 || *str_trim(end) || !(sec > 0) || sec > 86400) {
			snprintf(err, errlen, "playlist: '%s' is not NAME:SECONDS (seconds > 0)", e);
			return -1;
		}
		*colon = 0;
		char *name = str_trim(e);
		if (k->nshows == MAX_SHOWS) {
			snprintf(err, errlen, "playlist: more than %d shows", MAX_SHOWS);
			return -1;
		}
		struct show *s = &k->shows[k->nshows];
		snprintf(s->name, sizeof(s->name), "%s", name);
		size_t n = strlen(name);
		s->file = strchr(name, '/') || (n > 5 && !strcmp(name + n - 5, ".conf"));
		s->seconds = sec;
		struct params q; /* the preset or file applies (unknown preset: its list named) */
		char e2[512];
		if (show_params(s, &k->base, 0, &q, e2, sizeof(e2)) < 0) {
			snprintf(err, errlen, "playlist: %s", e2);
			return -1;
		}
		k->nshows++;
	}
	return 0;
}

/* A show's q into p: what can change live, the terrain (P_SHADER) and the
 * live settings (P_LIVE: the camera ...), not the animation time. */
static void apply_terrain(struct params *p, const struct params *q)
{
	for (size_t i = 0; i < param_count; i++) {
		const struct param_info *pi = &param_table[i];
		if ((pi->flags & (P_SHADER | P_LIVE)) && pi->type != PT_STRING && strcmp(pi->name, "time"))
			params_set_number(p, pi, params_get_number(q, pi));
	}
}

static void start_show(struct kiosk *k, struct params *p, int i, double t)
{
	const struct show *s = &k->shows[i];
	struct params q;
	char err[512];
	k->cur = i;
	/* from the last show's end (no drift), unless the run fell far behind */
	k->show_end = (k->started && t - k->show_end < s->seconds ? k->show_end : t) + s->seconds;
	if (show_params(s, &k->base, k->cycle, &q, err, sizeof(err)) < 0) {
		log_warn("playlist: %s; skipped", err); /* a file changed since the start */
		return;
	}
	apply_terrain(p, &q);
	k->show_start = k->show_end - s->seconds;
	log_info("playlist: show %d of %d, %s %s for %g s, cycle %ld, seed %d", i + 1, k->nshows,
		 s->file ? "config" : "preset", s->name, s->seconds, k->cycle + 1, q.seed);
}

/* ---- the crossfade ---------------------------------------------------------- */

/* The frame on the target now (the last show's last frame), kept by the
 * renderer for the crossfade. */
static void keep_last_frame(struct kiosk *k, struct renderer *r, double fade_s, double t)
{
	char err[256];
	k->fading = false;
	if (fade_s <= 0 || !r)
		return;
	if (renderer_keep_frame(r, err, sizeof(err)) < 0) {
		log_warn("playlist: %s: shows change with a cut", err);
		return;
	}
	k->fading = true;
	k->fade_r = r;
	k->fade_start = t;
	k->fade_s = fade_s;
	k->alpha = 1.0;
}

int kiosk_frame_end(struct kiosk *k, struct renderer *r, char *err, size_t errlen)
{
	if (!k || !k->fading || !r)
		return 0;
	if (r != k->fade_r) { /* a display's resize made another renderer: no fade */
		k->fading = false;
		return 0;
	}
	if (renderer_fade_kept(r, (float)k->alpha) < 0) {
		snprintf(err, errlen, "playlist crossfade failed");
		return -1;
	}
	return 0;
}

/* ---- reload ------------------------------------------------------------------ */

static bool differs(const struct params *a, const struct params *b, const struct param_info *pi)
{
	if (pi->type == PT_STRING)
		return strcmp((const char *)a + pi->offset, (const char *)b + pi->offset) != 0;
	return params_get_number(a, pi) != params_get_number(b, pi);
}

static void copy_param(struct params *to, const struct params *from, const struct param_info *pi)
{
	if (pi->type == PT_STRING)
		memcpy((char *)to + pi->offset, (const char *)from + pi->offset, PARAM_STR_MAX);
	else
		params_set_number(to, pi, params_get_number(from, pi));
}

static void reload(struct kiosk *k, struct params *p, double t)
{
	if (k->argc <= 0) {
		log_warn("config reload (SIGHUP): no command line kept: nothing to read again");
		return;
	}
	struct params q;
	char err[1024];
	enum cli_result rc = cli_parse(k->argc, k->argv, &q, err, sizeof(err));
	if (rc != CLI_RUN) {
		log_error("config reload (SIGHUP): %s; the running configuration is kept",
			  rc == CLI_ERROR ? err : "the command line now asks to exit");
		return;
	}
	struct kiosk trial = *k; /* the new playlist, checked before anything is applied */
	trial.base = q;
	if (differs(&k->base, &q, params_find("playlist")) &&
	    parse_playlist(&trial, q.playlist, err, sizeof(err)) < 0) {
		log_error("config reload (SIGHUP): %s; the running configuration is kept", err);
		return;
	}
	int applied = 0, restart = 0;
	bool playlist = false;
	struct params nb = q;
	for (size_t i = 0; i < param_count; i++) {
		const struct param_info *pi = &param_table[i];
		if (!strcmp(pi->name, "time") || !differs(&k->base, &q, pi))
			continue;
		char was[PARAM_STR_MAX], now[PARAM_STR_MAX];
		params_format(&k->base, pi, was, sizeof(was));
		params_format(&q, pi, now, sizeof(now));
		bool is_playlist = !strcmp(pi->name, "playlist") || !strcmp(pi->name, "playlist_fade");
		if ((pi->flags & (P_SHADER | P_LIVE)) || is_playlist) {
			copy_param(p, &q, pi);
			playlist |= is_playlist;
			applied++;
			log_info("config reload: %s = %s", pi->name, now);
		} else {
			copy_param(&nb, &k->base, pi);
			restart++;
			log_warn("config reload: %s '%s' -> '%s' needs a restart; '%s' kept", pi->name, was, now, was);
		}
	}
	k->base = nb;
	if (playlist) {
		memcpy(k->shows, trial.shows, sizeof(k->shows));
		k->nshows = trial.nshows;
		k->cycle = 0;
		k->started = false;
		if (k->nshows) {
			start_show(k, p, 0, t);
			k->started = true;
		}
	}
	log_info("config reload (SIGHUP): %d parameter%s applied, %d need%s a restart", applied,
		 applied == 1 ? "" : "s", restart, restart == 1 ? "s" : "");
}

/* ---- the kiosk --------------------------------------------------------------- */

struct kiosk *kiosk_create(struct params *p, int argc, char **argv, char *err, size_t errlen)
{
	struct kiosk *k = calloc(1, sizeof(*k));
	if (!k) {
		snprintf(err, errlen, "out of memory");
		return NULL;
	}
	k->argc = argc;
	k->argv = argv;
	k->base = *p;
	k->cur = -1;
	if (parse_playlist(k, p->playlist, err, errlen) < 0) {
		free(k);
		return NULL;
	}
	if (k->nshows) {
		start_show(k, p, 0, 0.0);
		k->started = true;
	}
	return k;
}

void kiosk_destroy(struct kiosk *k)
{
	free(k);
}

double kiosk_show_start(const struct kiosk *k)
{
	return k && k->nshows ? k->show_start : 0.0;
}

void kiosk_frame_begin(struct kiosk *k, struct params *p, struct renderer *r, double t)
{
	if (!k)
		return;
	if (signals_take_reload())
		reload(k, p, t);
	if (k->fading) {
		k->alpha = 1.0 - (t - k->fade_start) / k->fade_s;
		k->fading = k->alpha > 0.0;
	}
	if (k->nshows && k->started && t + 1e-9 >= k->show_end) {
		int next = k->cur + 1;
		if (next >= k->nshows) {
			next = 0;
			k->cycle++;
		}
		keep_last_frame(k, r, p->playlist_fade, t);
		start_show(k, p, next, t);
	}
}
