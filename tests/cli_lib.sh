# isoterra — shared helpers of the end-to-end CLI tests (sourced).
# Before sourcing: BIN, T (a scratch folder).  Optional: MAX_MSG_LINES (the
# most lines a refusal may print, default 3) and NO_OUTPUT (a file a refused
# run must not leave behind; removed before each run).
pass=0
fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*" >&2; }

# expect_fail "regex of the message" args...: a non-zero exit, the message,
# few lines, and no output file
expect_fail() {
	pat=$1
	shift
	[ -n "${NO_OUTPUT:-}" ] && rm -f "$NO_OUTPUT"
	"$BIN" "$@" >"$T/out" 2>"$T/err"
	rc=$?
	if [ $rc -eq 0 ]; then
		bad "isoterra $* exited 0"
		return
	fi
	if ! grep -Eq "$pat" "$T/err"; then
		bad "isoterra $*: message does not match '$pat': $(cat "$T/err")"
		return
	fi
	lines=$(grep -c . "$T/err")
	if [ "$lines" -gt "${MAX_MSG_LINES:-3}" ]; then
		bad "isoterra $*: $lines lines of messages, want one clear line: $(cat "$T/err")"
		return
	fi
	if [ -n "${NO_OUTPUT:-}" ] && [ -e "$NO_OUTPUT" ]; then
		bad "isoterra $*: failed but wrote $NO_OUTPUT"
		return
	fi
	ok
}
