#!/bin/sh
# isoterra — the results file (--results, app/output/sink_results.c) read
# back by Python's json module: the fields a dashboard reads, frame counts
# equal to --count, ordered percentiles, the renderer the run logs, the
# world's block counts, the volume's extractions (a static field's first
# frame only, a scrolling one's every frame), the frames after the first
# second (the hitches:
# null for a run shorter than that, else within the whole run's figures); a run that fails leaves an earlier results file as
# it was; --results - with --out - is refused; --fps-report works headless.
BIN=${1:-${ISOTERRA_BIN:-./build/isoterra}}
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
. "$(dirname "$0")/cli_lib.sh"
cd "$T" || exit 1

check_json() { # file count scene
	python3 - "$1" "$2" "$3" <<'PY'
import json, os, sys
path, count, scene = sys.argv[1], int(sys.argv[2]), sys.argv[3]
r = json.load(open(path))
bad = []
def need(cond, what):
    if not cond:
        bad.append(what)
need(r["run"]["frames"] == count, "frames %s != %d" % (r["run"]["frames"], count))
need(r["run"]["scene"] == scene, "scene %s" % r["run"]["scene"])
for k in ("frame_ms", "update_ms", "draw_ms"):
    d = r[k]
    need(0 <= d["p50"] <= d["p95"] <= d["p99"] <= d["max"], "%s percentiles out of order: %s" % (k, d))
need(r["frame_ms"]["mean"] >= r["update_ms"]["mean"] + r["draw_ms"]["mean"] - 1e-3,
     "a frame is shorter than its update and draw: %s" % r)
need(r["run"]["fps"] > 0 and abs(r["run"]["fps"] - 1000.0 / r["frame_ms"]["mean"]) < 0.01 * r["run"]["fps"] + 1e-3,
     "fps %s does not match the mean frame time %s" % (r["run"]["fps"], r["frame_ms"]["mean"]))
need(r["gl"]["renderer"] and r["gl"]["version"].startswith("OpenGL ES"), "gl %s" % r["gl"])
need(r["machine"]["cores"] >= 1 and len(r["machine"]["load_average"]) == 3, "machine %s" % r["machine"])
if scene == "world":
    need(r["blocks_generated"] > 0 and r["blocks_drawn"] > 0, "world blocks %s" % r)
    need(0 < r["blocks_skipped"] <= r["blocks_probed"], "world pre-pass: %s skipped of %s bounded" %
         (r["blocks_skipped"], r["blocks_probed"]))
else:
    need(r["triangles"] > 0, "volume triangles %s" % r["triangles"])
    # a static field is extracted by the first frame only; a scrolling
    # one by every frame (the caller says which: EXTRACTIONS)
    want = int(os.environ.get("EXTRACTIONS", "1"))
    need(r["extractions"] == want, "volume extracted %s times in %d frames, want %d" % (r["extractions"], count, want))
h = r["after_first_second"]
run_s = (r["frame_ms"]["mean"] * (count - 1)) / 1e3  # the frames after the first
if h is None:
    need(run_s < 1.0 + r["frame_ms"]["max"] / 1e3, "no frames after the first second in a run of %.2f s" % run_s)
else:
    need(0 < h["frames"] < count and run_s >= 1.0, "%s frames after the first second of %d in %.2f s" %
         (h["frames"], count, run_s))
    need(h["frames"] <= count - 1 - 1000.0 / r["frame_ms"]["max"] + 1, "%s frames after the first second: "
         "the first second cannot hold so few" % h["frames"])
    need(0 < h["p99"] <= h["max"] <= r["frame_ms"]["max"] + 1e-3, "hitches out of order: %s, %s" %
         (h, r["frame_ms"]))
    need(abs(h["max_over_p99"] - h["max"] / h["p99"]) < 1e-3 * h["max_over_p99"] + 1e-3, "max/p99 %s" % h)
    need(0 <= h["over_3x_p99"] <= h["frames"] // 100 + 1, "%s frames over 3 x the p99 of %s" %
         (h["over_3x_p99"], h["frames"]))
    need(1.0 <= h["worst_at_s"] <= run_s + 1e-3, "the worst frame at %s s of %.2f" % (h["worst_at_s"], run_s))
print("\n".join(bad) if bad else "ok")
sys.exit(1 if bad else 0)
PY
}

if "$BIN" --grid 24 --size 96x64 --count 4 --out v.png --results v.json --verbose 2>log; then
	if msg=$(check_json v.json 4 volume); then ok; else bad "volume results: $msg"; fi
	ren=$(python3 -c 'import json; print(json.load(open("v.json"))["gl"]["renderer"])')
	if grep -qF "$ren" log; then ok; else bad "the results name renderer '$ren', the log does not"; fi
else
	bad "volume run with --results failed: $(cat log)"
fi
# a scrolling field changes with time: every frame extracts it
if "$BIN" --grid 24 --size 96x64 --count 3 --scroll-speed 2 --out s.png --results s.json 2>log; then
	if msg=$(EXTRACTIONS=3 check_json s.json 3 volume); then ok; else bad "scrolling volume results: $msg"; fi
else
	bad "scrolling volume run with --results failed: $(cat log)"
fi
if "$BIN" --scene world --size 96x64 --count 3 --out w.png --results - >w.json 2>log; then
	if msg=$(check_json w.json 3 world); then ok; else bad "world results to stdout: $msg"; fi
else
	bad "world run with --results - failed: $(cat log)"
fi
# a run of a few seconds: its frames after the first second
if "$BIN" --scene world --size 96x64 --count 240 --out l.png --results l.json 2>log; then
	if msg=$(check_json l.json 240 world); then ok; else bad "world results of 240 frames: $msg"; fi
	if python3 -c 'import json,sys; sys.exit(json.load(open("l.json"))["after_first_second"] is None)'; then ok; else
		bad "240 frames and none after the first second: $(cat l.json)"
	fi
else
	bad "world run of 240 frames failed: $(cat log)"
fi
# a run that fails (its mesh cannot be written) leaves the earlier file
cp v.json keep.json
"$BIN" --grid 24 --size 96x64 --count 2 --out v2.png --results v.json --export-mesh /nonexistent/m.ply 2>/dev/null
if cmp -s v.json keep.json; then ok; else bad "a failed run changed the results file"; fi
expect_fail "standard output" --grid 8 --size 64x48 --out - --results -
# headless frame rate reports
"$BIN" --grid 24 --size 96x64 --count 6 --out f.png --fps-report 0.001 2>log >/dev/null
n=$(grep -c "fps .*headless" log)
if [ "$n" -ge 3 ]; then ok; else bad "--fps-report headless printed $n reports: $(cat log)"; fi
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
