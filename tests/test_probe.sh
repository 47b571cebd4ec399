#!/bin/sh
# isoterra — isoterra --probe (app/probe/): headless with a usable GL it
# exits 0, its text ends in the verdict and --results FILE is valid JSON with
# every section; an impossible job (a missing gpiochip, a missing V4L2
# device, a GL limit below a pass's need, --count 0 headless, a gbm platform
# where there is no card) exits 1 with the first blocking reason on the
# last line; a JSON file that cannot be written leaves none behind.
BIN=${1:-${ISOTERRA_BIN:-./build/isoterra}}
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
. "$(dirname "$0")/cli_lib.sh"
cd "$T" || exit 1
export XDG_CACHE_HOME="$T/cache"

check_json() { # file runs(true|false)
	python3 - "$1" "$2" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
want = sys.argv[2] == "true"
bad = []
for k in ("config", "egl", "drm", "gpio", "v4l2", "gl", "program_cache", "access", "verdict"):
    if k not in r:
        bad.append("no section " + k)
if not bad:
    if r["verdict"]["runs"] != want:
        bad.append("verdict.runs %s, want %s" % (r["verdict"]["runs"], want))
    if want and r["verdict"]["blocking"]:
        bad.append("blocking reasons on a job that runs: %s" % r["verdict"]["blocking"])
    if not want and not r["verdict"]["blocking"]:
        bad.append("no blocking reason on a job that does not run")
    if want:
        lim = r["gl"]["limits"]
        if len(lim) < 20:
            bad.append("only %d GL limits" % len(lim))
        for l in lim:
            if not l["ok"] or l["have"] < l["need"]:
                bad.append("limit %s not ok" % l["name"])
        if not any(l["needed_by"].startswith("density.comp") for l in lim):
            bad.append("no limit names the density pass: %s" % [l["needed_by"] for l in lim])
        if not any(l["needed_by"].startswith("render.vert + render.frag") for l in lim):
            bad.append("no limit names the terrain's shading program: %s" % [l["needed_by"] for l in lim])
        if not r["gl"]["programs_built"]:
            bad.append("the job's programs were not built")
        if not r["gl"]["platform"]:
            bad.append("no platform chosen")
    for k in ("client_extensions", "devices"):
        if k not in r["egl"]:
            bad.append("egl has no " + k)
    if "dir" not in r["program_cache"]:
        bad.append("program_cache has no dir")
if bad:
    print("; ".join(bad))
    sys.exit(1)
PY
}

# expect_block "regex of the last line" args...: exit 1, the reason last
expect_block() {
	pat=$1
	shift
	"$BIN" --probe "$@" >"$T/out" 2>"$T/err"
	rc=$?
	last=$(tail -n 1 "$T/out")
	if [ $rc -ne 1 ]; then
		bad "--probe $*: exit $rc, want 1 ($last)"
	elif ! printf '%s\n' "$last" | grep -Eq "NOT run.*$pat"; then
		bad "--probe $*: the last line does not name '$pat': $last"
	else
		ok
	fi
}

# the job as configured would run here: exit 0, the text's sections, JSON
if "$BIN" --probe --results "$T/p.json" >"$T/out" 2>"$T/err"; then
	ok
else
	bad "--probe exited $? headless: $(tail -n 3 "$T/out") $(cat "$T/err")"
fi
for s in '^EGL' '^DRM' '^GPIO' '^V4L2' '^Platform and GL' 'auto chooses' 'GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS' \
	'^Program cache' '^Access'; do
	grep -Eq "$s" "$T/out" || bad "--probe text has no '$s'"
done
tail -n 1 "$T/out" | grep -q 'the job would run' || bad "--probe: last line: $(tail -n 1 "$T/out")"
python3 -m json.tool "$T/p.json" >/dev/null || bad "--probe --results: not valid JSON"
m=$(check_json "$T/p.json" true) || bad "--probe JSON: $m"
ls "$T" | grep -q 'p.json.' && bad "--probe left a temp file: $(ls "$T")"
# --results -: the JSON alone on stdout
"$BIN" --probe --results - >"$T/stdout.json" 2>"$T/err" || bad "--probe --results - exited $?"
m=$(check_json "$T/stdout.json" true) || bad "--probe --results -: $m"

# impossible jobs: exit 1, the reason on the last line (and in the JSON)
expect_block "gpiochip99" --gpio-chip /dev/gpiochip99 --enc1-a 0 --enc1-b 1 --results "$T/b.json"
m=$(check_json "$T/b.json" false) || bad "--probe JSON of a blocked job: $m"
expect_block "--v4l2 /dev/video99" --v4l2 /dev/video99
export ISOTERRA_GL_LIMIT_OVERRIDE=GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS=3
expect_block "GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS is 3.*needs 4"
grep -Eq 'GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS +3 .*TOO LOW' "$T/out" || bad "--probe: the low limit is not marked"
unset ISOTERRA_GL_LIMIT_OVERRIDE
expect_block "count 0" --count 0 --platform surfaceless
if [ ! -e /dev/dri/card0 ]; then
	expect_block "drm-device|gbm|platform" --platform gbm --drm-device /dev/dri/card0
fi
expect_block "curves" --curves "$T/missing.geojson"

# a JSON file that cannot be written: exit 2, nothing left
"$BIN" --probe --results "$T/nodir/p.json" >/dev/null 2>&1
rc=$?
[ $rc -eq 2 ] || bad "--probe --results into a missing folder: exit $rc, want 2"

echo "probe: $pass passed, $fail failed"
[ $fail -eq 0 ]
