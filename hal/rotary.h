/* isoterra — quarter-step Gray-code decoder for mechanical rotary encoders.
 *
 * Pure C, no I/O: the GPIO layer feeds it line edges with their kernel
 * timestamps and reads back detents.
 *
 *   edges    -> debounce: a line's new level counts once it has been stable
 *               for debounce_ns (bounce = more edges of the same line inside
 *               that window; only the last level survives)
 *   levels   -> quarter steps: state = gray2bin(a,b) in 0..3; (last+1)%4 is
 *               +1, (state+1)%4 == last is -1, anything else (a two-step
 *               jump: both lines changed at once) is rejected and the decoder
 *               resynchronises on the new state — exactly the kernel's
 *               rotary_encoder quarter-period logic
 *   quarters -> detents: every steps_per_detent (1, 2 or 4) quarter steps in
 *               one direction give one detent; direction changes cancel
 *   detents  -> acceleration: a detent following the previous one in the
 *               same direction within accel_ns counts more (linear ramp up
 *               to accel_max at accel_ns / 4 and faster).
 *
 * Timestamps are nanoseconds on any monotonic clock. */
#ifndef ISOTERRA_ROTARY_H
#define ISOTERRA_ROTARY_H

#include <stdbool.h>
#include <stdint.h>

struct rotary_config {
	int steps_per_detent;  /* 1, 2 or 4 quarter steps per detent */
	uint64_t debounce_ns;  /* 0 = no debounce */
	uint64_t accel_ns;     /* detents closer than this accelerate; 0 = off */
	int accel_max;         /* largest multiplier (>= 1) */
};

struct rotary {
	struct rotary_config cfg;
	int level[2];           /* committed levels of A and B */
	int pending[2];         /* latest level seen per line (-1 none) */
	uint64_t pending_ts[2]; /* timestamp of that edge */
	int state;              /* last stable binary state 0..3 */
	int rest;               /* detent rest state (the state at init) */
	int quarters;           /* quarter steps towards the next detent */
	uint64_t last_detent_ts;
	int last_dir;
	/* counters (diagnostics, tests) */
	unsigned long illegal;  /* rejected two-step jumps */
	unsigned long bounces;  /* edges superseded inside the debounce window */
	unsigned long steps;    /* accepted quarter steps */
	int detents;            /* detents not yet taken (signed, accelerated) */
};

/* Returns false (and leaves r untouched) for an invalid configuration. */
bool rotary_init(struct rotary *r, const struct rotary_config *cfg, int a, int b);
/* Gray (a,b) -> binary position 0..3 along the sequence 00 01 11 10. */
int rotary_gray2bin(int a, int b);
/* One sample of both lines (levels read together, as the kernel driver
 * does on each interrupt): no debounce, a two-step jump is rejected. */
void rotary_sample(struct rotary *r, int a, int b, uint64_t ts_ns);
/* One edge: line 0 = A, 1 = B, its new level, the event's timestamp.  Edges
 * of both lines with the same timestamp that settle together form one
 * sample (so a simultaneous change of A and B is an illegal jump). */
void rotary_edge(struct rotary *r, int line, int level, uint64_t ts_ns);
/* Commits pending levels that have been stable for debounce_ns at time now
 * (call once per frame with the current time; rotary_edge calls it too). */
void rotary_flush(struct rotary *r, uint64_t now_ns);
/* Detents decoded since the last call (signed, acceleration applied). */
int rotary_take(struct rotary *r);



/* ---- push buttons: debounce from event timestamps ----------------------- */
struct button {
	uint64_t debounce_ns;
	int level;          /* committed level (1 = pressed) */
	int pending;        /* -1 none */
	uint64_t pending_ts;
	int presses;        /* presses (released -> pressed) not yet taken */
	unsigned long bounces;
};
void button_init(struct button *b, uint64_t debounce_ns, int level);
void button_edge(struct button *b, int level, uint64_t ts_ns);
void button_flush(struct button *b, uint64_t now_ns);
int button_take(struct button *b);
#endif
