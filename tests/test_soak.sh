#!/bin/sh
# isoterra — the soak's judgement (tools/soak.sh) in both directions:
#  - the series of window floors that failed CI's soak_world (one window
#    caught high at each end, the rest flat: least squares +2.67 MB/min),
#    the one that failed the package build's (two windows of six caught
#    high: the median of the window slopes +3.06) and a live process whose
#    resident size swings by 40 MB without growing pass: the floor of each
#    half of the judged time stays where it was;
#  - a series that grows in steps, and a live process that really grows
#    (1 MB a second), fail.
SOAK=${1:-${ISOTERRA_SRC:-.}/tools/soak.sh}
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
fails=0
bad() { echo "FAIL: $*"; fails=$((fails + 1)); }

# samples "t kB" of windows of 20 s every 5 s after a 60 s warm-up: each
# window's lowest sample is the floor given (MB), the others 12 MB above it
series() { # file floors...
	f=$1; shift
	: >"$f"
	for t in 0 5 10 15 20 25 30 35 40 45 50 55; do echo "$t 300000" >>"$f"; done
	t=60
	for mb in "$@"; do
		for k in 0 1 2 3; do
			kb=$(awk -v m="$mb" -v k="$k" 'BEGIN { printf "%d", (m + (k == 2 ? 0 : 12)) * 1024 }')
			echo "$t $kb" >>"$f"
			t=$((t + 5))
		done
	done
}
judge() { # expected-exit file [options]
	want=$1 f=$2; shift 2
	out=$("$SOAK" --duration 180 --interval 5 --warmup 60 --window 20 --max-slope 2 "$@" --judge "$f")
	rc=$?
	echo "$out"
	[ $rc -eq "$want" ] || echo "FAIL: $(basename "$f"): exit $rc, expected $want"
}
ls_slope() { echo "$1" | sed -n 's/.*least squares \([-+0-9.]*\)).*/\1/p'; }

series "$T/ci_noisy" 224.7 248.4 225.0 225.0 225.0 245.0
out=$(judge 0 "$T/ci_noisy") || true
echo "$out"
case $out in *FAIL*) fails=$((fails + 1)) ;; esac
# the old judgement (least squares) failed this very series
awk -v s="$(ls_slope "$out")" 'BEGIN { exit !(s > 2) }' || bad "ci_noisy: least squares $(ls_slope "$out") is not the +2.67 that failed CI"
case $out in *" 224.7 248.4 225.0 225.0 225.0 245.0 MB"*) ;; *) bad "ci_noisy: floors not reproduced" ;; esac

# the package build's soak_world under Debian 13 failed the median of the
# window slopes (+3.06 MB/min): flat at 145-146 with windows caught high
series "$T/pkg_noisy" 145.0 146.0 163.6 145.9 149.0 157.1
out=$(judge 0 "$T/pkg_noisy") || true
echo "$out"
case $out in *FAIL*) fails=$((fails + 1)) ;; esac
case $out in *"floor of each half 145.0 then 145.9 MB"*) ;; *) bad "pkg_noisy: halves' floors not 145.0 then 145.9" ;; esac

series "$T/steps" 225 225 235 235 245 245 # 10 MB every 40 s
out=$(judge 1 "$T/steps") || true
echo "$out"
case $out in *FAIL*) fails=$((fails + 1)) ;; esac

series "$T/slow" 225 226 227 228 229 230 # 3 MB/min, steady
out=$(judge 1 "$T/slow") || true
echo "$out"
case $out in *FAIL*) fails=$((fails + 1)) ;; esac

# live: a process that grows by 1 MB (touched) every second must fail; one
# that holds 40 MB every other 0.35 s and frees it (over the largest mmap
# threshold glibc adapts to: unmapped when freed) must pass
# (the two run side by side: each mostly sleeps, and 40 s is the soak's own
# length, not work)
if command -v python3 >/dev/null; then
	"$SOAK" --duration 40 --interval 1 --warmup 10 --window 5 --max-slope 2 -- python3 -c '
import time
keep = []
while True:
    keep.append(b"x" * (1 << 20))
    time.sleep(1)' >"$T/leaking.out" 2>&1 &
	leaking=$!
	"$SOAK" --duration 40 --interval 1 --warmup 10 --window 5 --max-slope 2 -- python3 -c '
import time
n = 0
while True:
    block = b"x" * (40 << 20) if n % 2 else None
    n += 1
    time.sleep(0.35)' >"$T/swinging.out" 2>&1
	rc_swing=$?
	wait "$leaking"
	rc=$?
	echo "leaking child: $(cat "$T/leaking.out")"
	[ $rc -eq 1 ] || bad "a child growing 1 MB/s passed the soak (exit $rc)"
	echo "swinging child: $(cat "$T/swinging.out")"
	[ $rc_swing -eq 0 ] || bad "a child swinging by 40 MB without growing failed the soak (exit $rc_swing)"
else
	echo "SKIP live children: no python3"
fi
[ $fails -eq 0 ] && echo "soak judgement: all checks passed"
exit $((fails > 0))
