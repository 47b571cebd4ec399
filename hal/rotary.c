/* isoterra — quarter-step Gray-code decoder (see rotary.h). */
#include "rotary.h"

#include <string.h>

int rotary_gray2bin(int a, int b)
{
	a = !!a;
	b = !!b;
	/* gray g1 g0 = a b  ->  binary b1 = g1, b0 = g1 ^ g0: 00 01 11 10 -> 0 1 2 3 */
	return (a << 1) | (a ^ b);
}

bool rotary_init(struct rotary *r, const struct rotary_config *cfg, int a, int b)
{
	if (cfg->steps_per_detent != 1 && cfg->steps_per_detent != 2 && cfg->steps_per_detent != 4)
		return false;
	if (cfg->accel_max < 1)
		return false;
	memset(r, 0, sizeof(*r));
	r->cfg = *cfg;
	r->level[0] = !!a;
	r->level[1] = !!b;
	r->pending[0] = r->pending[1] = -1;
	r->state = r->rest = rotary_gray2bin(a, b);
	return true;
}

static void detent(struct rotary *r, int d, uint64_t ts)
{
	int dir = d > 0 ? 1 : -1;
	int mult = 1;
	const struct rotary_config *c = &r->cfg;
	if (c->accel_ns && c->accel_max > 1 && dir == r->last_dir && r->last_detent_ts && ts >= r->last_detent_ts) {
		uint64_t dt = ts - r->last_detent_ts;
		uint64_t full = c->accel_ns / 4; /* full speed-up at a quarter of the window */
		if (dt <= full)
			mult = c->accel_max;
		else if (dt < c->accel_ns)
			mult = 1 + (int)((uint64_t)(c->accel_max - 1) * (c->accel_ns - dt) / (c->accel_ns - full));
	}
	r->last_dir = dir;
	r->last_detent_ts = ts;
	r->detents += d * mult;
}

void rotary_sample(struct rotary *r, int a, int b, uint64_t ts_ns)
{
	r->level[0] = !!a;
	r->level[1] = !!b;
	int ns = rotary_gray2bin(a, b);
	if (ns == r->state)
		return;
	int dir;
	if ((r->state + 1) % 4 == ns) {
		dir = 1;
	} else if ((ns + 1) % 4 == r->state) {
		dir = -1;
	} else {
		/* two-step jump: direction unknown; resynchronise (kernel behaviour) */
		r->illegal++;
		r->state = ns;
		return;
	}
	r->state = ns;
	r->steps++;
	r->quarters += dir;
	int spd = r->cfg.steps_per_detent;
	if (ns % spd == r->rest % spd) {
		/* at a rest position: whole detents since the last one; after a
		 * rejected jump the count may be off by two, round to nearest */
		int q = r->quarters;
		int d = q >= 0 ? (q + spd / 2) / spd : -((-q + spd / 2) / spd);
		if (spd == 1)
			d = q;
		r->quarters = 0;
		if (d)
			detent(r, d, ts_ns);
	}
}

static void commit(struct rotary *r, int line, int level, uint64_t ts)
{
	int a = line == 0 ? level : r->level[0];
	int b = line == 1 ? level : r->level[1];
	rotary_sample(r, a, b, ts);
}

void rotary_flush(struct rotary *r, uint64_t now_ns)
{
	uint64_t db = r->cfg.debounce_ns;
	bool ready[2];
	for (int i = 0; i < 2; i++)
		ready[i] = r->pending[i] >= 0 && now_ns >= r->pending_ts[i] && now_ns - r->pending_ts[i] >= db;
	if (ready[0] && ready[1] && r->pending_ts[0] == r->pending_ts[1]) {
		/* both lines changed at the same instant: one sample */
		int a = r->pending[0], b = r->pending[1];
		r->pending[0] = r->pending[1] = -1;
		rotary_sample(r, a, b, r->pending_ts[0]);
		return;
	}
	/* in the order the edges happened */
	int first = ready[0] && ready[1] ? (r->pending_ts[1] < r->pending_ts[0]) : (ready[1] ? 1 : 0);
	for (int k = 0; k < 2; k++) {
		int i = k == 0 ? first : !first;
		if (!ready[i])
			continue;
		int lv = r->pending[i];
		r->pending[i] = -1;
		commit(r, i, lv, r->pending_ts[i]);
	}
}

void rotary_edge(struct rotary *r, int line, int level, uint64_t ts_ns)
{
	if (line < 0 || line > 1)
		return;
	level = !!level;
	if (r->cfg.debounce_ns == 0) {
		/* the other line cannot be pending without debounce */
		commit(r, line, level, ts_ns);
		return;
	}
	/* an edge of the other line at the very same instant is kept pending
	 * so that the two settle together; anything older that has settled
	 * goes first */
	rotary_flush(r, ts_ns);
	if (r->pending[line] >= 0)
		r->bounces++; /* superseded inside the debounce window */
	r->pending[line] = level;
	r->pending_ts[line] = ts_ns;
}

int rotary_take(struct rotary *r)
{
	int d = r->detents;
	r->detents = 0;
	return d;
}

void button_init(struct button *b, uint64_t debounce_ns, int level)
{
	memset(b, 0, sizeof(*b));
	b->debounce_ns = debounce_ns;
	b->level = !!level;
	b->pending = -1;
}

void button_flush(struct button *b, uint64_t now_ns)
{
	if (b->pending < 0 || now_ns < b->pending_ts || now_ns - b->pending_ts < b->debounce_ns)
		return;
	if (b->pending && !b->level)
		b->presses++;
	b->level = b->pending;
	b->pending = -1;
}

void button_edge(struct button *b, int level, uint64_t ts_ns)
{
	button_flush(b, ts_ns);
	if (b->pending >= 0)
		b->bounces++;
	b->pending = !!level;
	b->pending_ts = ts_ns;
	if (b->debounce_ns == 0)
		button_flush(b, ts_ns);
}

int button_take(struct button *b)
{
	int n = b->presses;
	b->presses = 0;
	return n;
}
