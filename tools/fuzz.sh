#!/bin/sh
# isoterra — the libFuzzer harnesses of tests/fuzz/: configure (clang,
# -Dfuzz=true) and build them in build-fuzz/, then run each for SECONDS
# (default 60) or, with FUZZ_RUNS=N, for N executions, under ASan+UBSan.
# Each starts from its committed seeds (tests/fuzz/corpus/NAME) and the
# inputs that once failed it (tests/fuzz/regress/NAME), all replayed at
# start, and keeps what it finds in build-fuzz/corpus/NAME; crashes are
# written to build-fuzz/crash-NAME-*.  The readers that take a path get
# their input as a file under $FUZZ_TMPDIR (default /dev/shm: a
# disk-backed /tmp makes them ~20 times slower).  Exit status 1 when any
# harness fails.  Limits per input: 10 s, 2 GB resident, no single
# allocation over 1.5 GB (more than the largest valid heightmap needs).
#   tools/fuzz.sh [SECONDS [NAME...]]      FUZZ_RUNS=N: at most N executions
#                                          each, and at most SECONDS
set -u
cd "$(dirname "$0")/.."
secs=${1:-60}
[ $# -gt 0 ] && shift
names=${*:-config cli geojson gpx csv heightmap ply evdev}
B=${FUZZ_BUILD:-build-fuzz}
if [ ! -d "$B" ]; then
	CC=clang meson setup "$B" -Dfuzz=true -Dwerror=true >"$B.setup.log" 2>&1 || { cat "$B.setup.log"; exit 1; }
fi
targets=""
for n in $names; do targets="$targets tests/fuzz/fuzz_$n"; done
# shellcheck disable=SC2086 # a word list on purpose
ninja -C "$B" $targets || exit 1
TMPDIR=${FUZZ_TMPDIR:-/dev/shm}
[ -d "$TMPDIR" ] && [ -w "$TMPDIR" ] || TMPDIR=/tmp
export TMPDIR
runs=-runs=-1
[ -n "${FUZZ_RUNS:-}" ] && runs="-runs=$FUZZ_RUNS"
# FUZZ_JOBS harnesses at a time (default: the online CPUs): each is one
# process, so on 2 cores two 60 s runs take 60 s of wall time, not 120
jobs=${FUZZ_JOBS:-$(getconf _NPROCESSORS_ONLN 2>/dev/null || echo 1)}
case $jobs in ''|*[!0-9]*|0) jobs=1 ;; esac
fuzz_one() { # name: runs one harness; its exit status goes to $B/fuzz-NAME.rc
	n=$1
	mkdir -p "$B/corpus/$n"
	regress=""
	[ -d "tests/fuzz/regress/$n" ] && regress="tests/fuzz/regress/$n"
	# shellcheck disable=SC2086 # $regress: nothing or one folder
	"$B/tests/fuzz/fuzz_$n" "$runs" -max_total_time="$secs" -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=1536 \
		-print_final_stats=1 -dict="tests/fuzz/$n.dict" -artifact_prefix="$B/crash-$n-" \
		"$B/corpus/$n" "tests/fuzz/corpus/$n" $regress >"$B/fuzz-$n.log" 2>&1
	echo $? >"$B/fuzz-$n.rc"
}
running=0
for n in $names; do
	rm -f "$B/fuzz-$n.rc"
	fuzz_one "$n" &
	running=$((running + 1))
	if [ $running -ge "$jobs" ]; then
		wait
		running=0
	fi
done
wait
pass=0
fail=0
for n in $names; do
	log="$B/fuzz-$n.log"
	rc=$(cat "$B/fuzz-$n.rc" 2>/dev/null || echo 1)
	execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
	t=$(sed -n 's/^Done [0-9]* runs in \([0-9]*\) second.*/\1/p' "$log" | tail -1)
	rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
	if [ $rc -eq 0 ]; then
		pass=$((pass + 1))
		echo "fuzz $n: ${execs:-?} executions in ${t:-?} s (${rate:-?}/s), no crash"
	else
		fail=$((fail + 1))
		echo "FAIL: fuzz $n (exit $rc), $log:" >&2
		grep -E "ERROR|SUMMARY|Test unit written" "$log" >&2
	fi
done
echo "== fuzz: $pass passed, $fail failed"
[ $fail -eq 0 ]
