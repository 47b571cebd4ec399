# isoterra — shared helpers of the display tests (sourced).
# Env (set by meson): ISOTERRA_BIN, IMGCMP, ISOTERRA_SRC.
# ISOTERRA_REQUIRE_DEVICE_TESTS=1 (tools/test-all.sh sets it) turns a
# missing tool into a failure instead of a skip.
BIN=${ISOTERRA_BIN:-./build/isoterra}
IMGCMP=${IMGCMP:-./build/tests/imgcmp}
pass=0
fail=0
ok() { pass=$((pass + 1)); echo "ok: $*"; }
bad() { fail=$((fail + 1)); echo "FAIL: $*" >&2; }

# scratch: a scratch folder $T, removed on exit (ISOTERRA_KEEP=1 keeps it),
# with the app ($APID, killed) and the display server ($SERVER_PID,
# terminated) stopped on exit
scratch() {
	T=$(mktemp -d)
	APID=
	SERVER_PID=
	trap 'scratch_cleanup' EXIT
}
scratch_cleanup() {
	[ -n "$APID" ] && kill -KILL "$APID" 2>/dev/null
	[ -n "$SERVER_PID" ] && kill -TERM "$SERVER_PID" 2>/dev/null
	[ "${ISOTERRA_KEEP:-0}" = 1 ] || rm -rf "$T"
}

# need TOOL... : skip (77) when a tool is missing, unless required.
need() {
	for t in "$@"; do
		if ! command -v "$t" >/dev/null 2>&1 && [ ! -x "$t" ]; then
			if [ "${ISOTERRA_REQUIRE_DEVICE_TESTS:-0}" = 1 ]; then
				echo "FAIL: '$t' is not installed (sh tools/deps.sh installs it)" >&2
				echo "0 passed, 1 failed"
				exit 1
			fi
			echo "skip: '$t' is not installed (sh tools/deps.sh installs it)"
			exit 77
		fi
	done
}

# alive PID: running (a zombie child, exited but not yet waited for, is not)
alive() {
	_s=$(ps -o stat= -p "$1" 2>/dev/null)
	[ -n "$_s" ] && [ "${_s#Z}" = "$_s" ]
}

# wait_for FILE REGEX SECONDS [PID]: until FILE has a line matching REGEX;
# 1 on timeout or when PID died first.
wait_for() {
	_n=0
	while [ $_n -lt $(($3 * 10)) ]; do
		grep -Eq "$2" "$1" 2>/dev/null && return 0
		if [ -n "${4:-}" ] && ! alive "$4"; then
			grep -Eq "$2" "$1" 2>/dev/null && return 0
			return 1
		fi
		sleep 0.1
		_n=$((_n + 1))
	done
	return 1
}

# presented FILE: the highest "N presented" count in an --fps-report log.
presented() {
	grep -oE '[0-9]+ presented' "$1" 2>/dev/null | awk '{ if ($1 > m) m = $1 } END { print m + 0 }'
}

# wait_frames LOG N SECONDS PID: until the app reports >= N frames presented.
wait_frames() {
	_n=0
	while [ $_n -lt $(($3 * 10)) ]; do
		[ "$(presented "$1")" -ge "$2" ] && return 0
		alive "$4" || return 1
		sleep 0.1
		_n=$((_n + 1))
	done
	return 1
}

# wait_size LOG WxH SECONDS PID: until a frame-rate report shows the window
# at WxH (a fullscreen configure can arrive after the first frames, which
# are then scaled to the output), then two more frames presented.
wait_size() {
	_n=0
	while [ $_n -lt $(($3 * 10)) ]; do
		if grep -q "shown, $2 " "$1" 2>/dev/null; then
			wait_frames "$1" $(($(presented "$1") + 2)) "$3" "$4"
			return
		fi
		alive "$4" || return 1
		sleep 0.1
		_n=$((_n + 1))
	done
	return 1
}

# stop PID [SECONDS]: SIGTERM, wait (20 s by default); sets RC to the exit
# status, or "timeout" (then the app was killed).  Not in $(...): only the
# parent shell can wait for the app.
stop() {
	kill -TERM "$1" 2>/dev/null
	_n=0
	while alive "$1" && [ $_n -lt $((${2:-20} * 10)) ]; do sleep 0.1; _n=$((_n + 1)); done
	if alive "$1"; then
		kill -KILL "$1" 2>/dev/null
		wait "$1" 2>/dev/null
		RC=timeout
		return
	fi
	wait "$1"
	RC=$?
}

# headless REF.png WxH args...: the same frame rendered headless.
headless() {
	_out=$1
	_size=$2
	shift 2
	"$BIN" --platform surfaceless --size "$_size" --out "$_out" "$@" >"$_out.log" 2>&1 ||
		{ bad "headless reference render failed: $(cat "$_out.log")"; return 1; }
}

# compare WHAT GRAB REF [imgcmp limits]: the grab matches the reference.
compare() {
	_what=$1
	shift
	if "$IMGCMP" "$@" >"$T/cmp.txt" 2>&1; then
		ok "$_what: $(cat "$T/cmp.txt")"
	else
		bad "$_what: $(cat "$T/cmp.txt")"
		"$IMGCMP" --to-png "$1" "$T/fail-$(basename "$1").png" 2>/dev/null &&
			echo "   (grab kept as $T/fail-$(basename "$1").png; set ISOTERRA_KEEP=1 to keep $T)" >&2
	fi
}

# wait_caught PID SIGNUM SECONDS: until the process has a handler for the
# signal (its SigCgt mask in /proc), so a signal sent next is not fatal
# because it came before the handler; 1 on timeout or when it is gone
wait_caught() {
	_bit=$(( 1 << ($2 - 1) ))
	_n=0
	while [ $_n -lt $(( $3 * 10 )) ]; do
		_mask=$(awk '/^SigCgt:/ {print $2}' "/proc/$1/status" 2>/dev/null) || return 1
		[ -n "$_mask" ] || return 1
		[ $(( 0x$_mask & _bit )) -ne 0 ] && return 0
		sleep 0.1
		_n=$((_n + 1))
	done
	return 1
}
