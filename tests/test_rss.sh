#!/bin/sh
# isoterra — the world's peak resident memory stays under the ceiling
# docs/RELIABILITY.md ("Memory", "The ceiling") derives for this run:
# 60 frames of the world scene at 640x360, written as PNG frames.  The peak
# is the kernel's own (getrusage of the finished child: ru_maxrss, the
# VmHWM it had), taken by python3.  Plain builds only (a sanitizer's shadow
# memory is not the program's).
BIN=${1:-${ISOTERRA_BIN:-./build/isoterra}}
CEILING_MB=${2:-185}
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
python3 - "$BIN" "$CEILING_MB" "$T" <<'PY'
import resource, subprocess, sys
bin, ceiling, tmp = sys.argv[1], float(sys.argv[2]), sys.argv[3]
cmd = [bin, "--scene", "world", "--count", "60", "--size", "640x360", "--platform", "surfaceless",
       "--out", tmp + "/f%03d.png"]
r = subprocess.run(cmd, capture_output=True, text=True)
if r.returncode != 0:
    print("FAIL: %s exited %d: %s" % (" ".join(cmd), r.returncode, r.stderr.strip()[-500:]))
    sys.exit(1)
peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024.0  # kB -> MiB
print("world 640x360, 60 frames: peak RSS %.1f MiB, ceiling %.0f MiB (margin %.1f MiB)" % (peak, ceiling, ceiling - peak))
print(r.stderr.strip().splitlines()[-1] if r.stderr.strip() else "")
if peak > ceiling:
    print("FAIL: the world's peak RSS %.1f MiB is over its ceiling of %.0f MiB" % (peak, ceiling))
    sys.exit(1)
PY
