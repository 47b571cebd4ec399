#!/bin/sh
# isoterra — soak: runs isoterra for a while, samples its resident memory
# (VmRSS) and fails when it keeps growing after the warm-up.
#
#   tools/soak.sh [options] -- ISOTERRA [ARGS...]
#   tools/soak.sh [options] --judge FILE     judge samples taken before
#     --duration S    how long to sample (default 180)
#     --interval S    seconds between samples (default 5)
#     --warmup S      samples before this are not judged (default 60)
#     --window S      the windows whose lowest samples are printed (default
#                     20 s): the floor the process comes back to, not the
#                     frame in flight
#     --max-slope M   growth allowed after the warm-up, MB per minute
#                     (default 2), judged on the floor: the lowest sample of
#                     the second half of the judged time against the lowest
#                     of the first half, over the time between the halves'
#                     centres.  Memory held for a moment (a frame's bins)
#                     only ever adds to what the process keeps, so it moves
#                     the floors of neither half as long as each half comes
#                     back to its floor once; what the process keeps for good
#                     (a leak, steady or in steps) raises the second floor.
#                     The median of the slopes between every two window
#                     floors (Theil-Sen) and the least-squares line are
#                     printed beside it for comparison
#     --from-output   the clock starts at the program's first byte on
#                     standard output (e.g. with --out -, the Y4M stream:
#                     after the first frame), so a slow start-up (the world's
#                     first fill) is neither sampled nor judged; waits for
#                     it at most 600 s
#     --log FILE      the samples, "seconds rss_kB" per line, written as
#                     they are taken (default: a temporary file)
#     --judge FILE    run nothing: judge the samples in FILE (a --log of an
#                     earlier run) with the options given
#
# After the duration the program gets SIGTERM.  Fails (exit 1) when the
# program ends by itself before, when the floor's slope is over --max-slope,
# or when there are fewer than 3 windows to judge.  Prints the window floors,
# the two halves' floors and their slope, the median and least-squares
# slopes (for comparison) and the band of all samples after the warm-up.  docs/RELIABILITY.md ("Soak") says what the
# limits mean.
duration=180 interval=5 warmup=60 window=20 max_slope=2 log= from_output= judge=
while [ $# -gt 0 ]; do
	case $1 in
	--duration) duration=$2; shift 2 ;;
	--interval) interval=$2; shift 2 ;;
	--warmup) warmup=$2; shift 2 ;;
	--window) window=$2; shift 2 ;;
	--max-slope) max_slope=$2; shift 2 ;;
	--from-output) from_output=1; shift ;;
	--log) log=$2; shift 2 ;;
	--judge) judge=$2; shift 2 ;;
	--) shift; break ;;
	*) echo "soak: unknown option '$1' (see the head of $0)" >&2; exit 2 ;;
	esac
done
[ $# -ge 1 ] || [ -n "$judge" ] || { echo "soak: no program to run (tools/soak.sh [options] -- ISOTERRA ARGS...)" >&2; exit 2; }
[ -z "$judge" ] || [ -r "$judge" ] || { echo "soak: cannot read --judge '$judge'" >&2; exit 2; }
for v in "$duration" "$interval" "$warmup" "$window"; do
	case $v in ''|*[!0-9]*) echo "soak: '$v' is not a whole number of seconds" >&2; exit 2 ;; esac
done
case $max_slope in ''|*[!0-9.]*) echo "soak: --max-slope '$max_slope' is not a number" >&2; exit 2 ;; esac
[ "$interval" -ge 1 ] && [ "$window" -ge "$interval" ] && [ "$warmup" -lt "$duration" ] ||
	{ echo "soak: need --interval >= 1, --window >= --interval and --warmup < --duration" >&2; exit 2; }

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
died=
if [ -n "$judge" ]; then
	samples=$judge
else
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
fi
# The window floors after the warm-up ("t floor_kB" lines, in order), then
# the slope between every two of them (kB/s) for the median.
floors=$tmp/floors
awk -v w="$warmup" -v win="$window" '
	$1 < w { next }
	{ k = int(($1 - w) / win); if (!(k in lo) || $2 < lo[k]) lo[k] = $2; if (k > kmax) kmax = k }
	END { for (k = 0; k <= kmax; k++) if (k in lo) printf "%.1f %d\n", w + (k + 0.5) * win, lo[k] }' "$samples" >"$floors"
median=$(awk '{ t[NR] = $1; f[NR] = $2 }
	END { for (i = 1; i <= NR; i++) for (j = i + 1; j <= NR; j++) printf "%.9g\n", (f[j] - f[i]) / (t[j] - t[i]) }' "$floors" |
	sort -g | awk '{ s[NR] = $1 } END { if (NR) print (NR % 2 ? s[(NR + 1) / 2] : (s[NR / 2] + s[NR / 2 + 1]) / 2); else print 0 }')
awk -v w="$warmup" -v win="$window" -v max="$max_slope" -v died="$died" -v median="$median" -v floors="$floors" '
	$1 < w { next }
	{ if (!ns || $2 < blo) blo = $2; if (!ns || $2 > bhi) bhi = $2; ns++; st[ns] = $1; sv[ns] = $2; tend = $1 }
	END {
		while ((getline line < floors) > 0) {
			split(line, a, " "); n++; fl[n] = a[2]
			x += a[1]; y += a[2]; xx += a[1] * a[1]; xy += a[1] * a[2]
		}
		if (n < 3) { printf "soak: %d windows after the %d s warm-up: too few to judge\n", n, w; exit 1 }
		# the two halves of the judged time, and the lowest sample of each
		mid = (w + tend) / 2
		for (i = 1; i <= ns; i++)
			if (st[i] < mid) { if (!n1 || sv[i] < lo1) lo1 = sv[i]; n1++ }
			else { if (!n2 || sv[i] < lo2) lo2 = sv[i]; n2++ }
		if (!n1 || !n2) { printf "soak: %d samples after the %d s warm-up: too few to judge\n", ns, w; exit 1 }
		slope = (lo2 - lo1) / ((tend - w) / 2) * 60 / 1024
		ts = median * 60 / 1024
		ls = (n * xy - x * y) / (n * xx - x * x) * 60 / 1024
		printf "soak: floors of %d windows of %d s after the %d s warm-up:", n, win, w
		for (k = 1; k <= n; k++) printf " %.1f", fl[k] / 1024
		printf " MB; floor of each half %.1f then %.1f MB: %+.2f MB/min (limit %s; median of window slopes %+.2f, least squares %+.2f); all %d samples after the warm-up %.1f-%.1f MB (band %.1f MB)\n",
			lo1 / 1024, lo2 / 1024, slope, max, ts, ls, ns, blo / 1024, bhi / 1024, (bhi - blo) / 1024
		exit (slope > max || died != "") ? 1 : 0
	}' "$samples"
