#!/bin/sh
# isoterra — soak: runs isoterra for a while, samples its resident memory
# (VmRSS) and fails when it keeps growing after the warm-up.
#
#   tools/soak.sh [options] -- ISOTERRA [ARGS...]
#     --duration S    how long to sample (default 180)
#     --interval S    seconds between samples (default 5)
#     --warmup S      samples before this are not judged (default 60)
#     --window S      the judged series: the lowest sample of each window of
#                     S seconds after the warm-up (default 20): the floor the
#                     process comes back to, not the frame in flight
#     --max-slope M   growth allowed after the warm-up, MB per minute: the
#                     least-squares slope of the window floors (default 2)
#     --from-output   the clock starts at the program's first byte on
#                     standard output (e.g. with --out -, the Y4M stream:
#                     after the first frame), so a slow start-up (the world's
#                     first fill) is neither sampled nor judged; waits for
#                     it at most 600 s
#     --log FILE      the samples, "seconds rss_kB" per line, written as
#                     they are taken (default: a temporary file)
#
# After the duration the program gets SIGTERM.  Fails (exit 1) when the
# program ends by itself before, when the slope is over --max-slope, or when
# there are fewer than 3 windows to judge.  Prints the floors and the band
# of all samples after the warm-up.  docs/RELIABILITY.md ("Soak") says what
# the limits mean.
duration=180 interval=5 warmup=60 window=20 max_slope=2 log= from_output=
while [ $# -gt 0 ]; do
	case $1 in
	--duration) duration=$2; shift 2 ;;
	--interval) interval=$2; shift 2 ;;
	--warmup) warmup=$2; shift 2 ;;
	--window) window=$2; shift 2 ;;
	--max-slope) max_slope=$2; shift 2 ;;
	--from-output) from_output=1; shift ;;
	--log) log=$2; shift 2 ;;
	--) shift; break ;;
	*) echo "soak: unknown option '$1' (see the head of $0)" >&2; exit 2 ;;
	esac
done
[ $# -ge 1 ] || { echo "soak: no program to run (tools/soak.sh [options] -- ISOTERRA ARGS...)" >&2; exit 2; }
for v in "$duration" "$interval" "$warmup" "$window"; do
	case $v in ''|*[!0-9]*) echo "soak: '$v' is not a whole number of seconds" >&2; exit 2 ;; esac
done
case $max_slope in ''|*[!0-9.]*) echo "soak: --max-slope '$max_slope' is not a number" >&2; exit 2 ;; esac
[ "$interval" -ge 1 ] && [ "$window" -ge "$interval" ] && [ "$warmup" -lt "$duration" ] ||
	{ echo "soak: need --interval >= 1, --window >= --interval and --warmup < --duration" >&2; exit 2; }

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
samples=${log:-$tmp/samples}
: >"$samples" || exit 2
"$@" >>"$tmp/stdout" 2>"$tmp/stderr" &
pid=$!
if [ -n "$from_output" ]; then
	n=0
	while [ ! -s "$tmp/stdout" ] && kill -0 $pid 2>/dev/null && [ $n -lt 6000 ]; do
		sleep 0.1
		n=$((n + 1))
	done
	[ -s "$tmp/stdout" ] || { echo "soak: no output from the program in $((n / 10)) s: $(tail -3 "$tmp/stderr")"; kill -KILL $pid 2>/dev/null; exit 1; }
	echo "soak: first output after $((n / 10)) s"
fi
start=$(date +%s)
died=
while :; do
	now=$(($(date +%s) - start))
	[ $now -ge "$duration" ] && break
	rss=$(awk '/^VmRSS:/ { print $2 }' "/proc/$pid/status" 2>/dev/null)
	if [ -z "$rss" ] || ! kill -0 $pid 2>/dev/null; then
		died=$now
		break
	fi
	echo "$now $rss" >>"$samples"
	# the output is only a clock: keep it small
	[ -n "$from_output" ] && : >"$tmp/stdout"
	sleep "$interval"
done
if [ -z "$died" ]; then
	kill -TERM $pid 2>/dev/null
	wait $pid 2>/dev/null
else
	wait $pid
	echo "soak: the program ended after $died s (exit $?), before the $duration s: $(tail -3 "$tmp/stderr")"
fi
# window floors after the warm-up; least squares over them: kB/s -> MB/min
awk -v w="$warmup" -v win="$window" -v max="$max_slope" -v died="$died" '
	$1 < w { first = $2; next }
	{ k = int(($1 - w) / win); if (!(k in lo) || $2 < lo[k]) lo[k] = $2; t[k] = w + (k + 0.5) * win
	  if (!ns || $2 < blo) blo = $2; if (!ns || $2 > bhi) bhi = $2; ns++ }
	END {
		for (k in lo) { n++; x += t[k]; y += lo[k]; xx += t[k] * t[k]; xy += t[k] * lo[k] }
		if (n < 3) { printf "soak: %d windows after the %d s warm-up: too few to judge\n", n, w; exit 1 }
		slope = (n * xy - x * y) / (n * xx - x * x) * 60 / 1024
		printf "soak: floors of %d windows of %d s after the %d s warm-up:", n, win, w
		for (k = 0; k in lo; k++) printf " %.1f", lo[k] / 1024
		printf " MB; slope %+.2f MB/min (limit %s); all %d samples after the warm-up %.1f-%.1f MB (band %.1f MB)\n",
			slope, max, ns, blo / 1024, bhi / 1024, (bhi - blo) / 1024
		exit (slope > max || died != "") ? 1 : 0
	}' "$samples"
