#!/bin/sh
# isoterra — the GPU tests and the benchmarks on this machine's GPU, through
# EGL_EXT_platform_device (--platform device), into ONE results file (JSON):
# the machine, the EGL device and its GL renderer, version and driver, each
# test's result and check counts, and the figures of bench/bench_pipeline
# and bench/bench_world (and the program's own start and peak memory).
#
#   sh tools/gpu-suite.sh [--build DIR] [--out FILE] [--quick] [--device N|PATH]
#                         [--platform NAME] [--tests NAME,NAME] [--no-bench] [--no-tests]
#
#   --build DIR        a built tree (default: build); a copy carried from
#                      another machine works: the tests are run from its
#                      meson-info/intro-tests.json with its paths moved to
#                      where DIR and this checkout are now, without meson,
#                      ninja or the GL headers (python3 is needed)
#   --out FILE         the results (default: gpu-suite.json)
#   --quick            the benchmarks' quick modes, and no gallery test
#                      (about 10 minutes on llvmpipe with 2 cores; seconds
#                      of GPU time on a GPU)
#   --device N|PATH    the EGL device (an index as `isoterra --list-devices`
#                      shows it, or a DRM node): ISOTERRA_DEVICE for the
#                      tests, the benchmarks and the program
#   --platform NAME    instead of device (surfaceless: llvmpipe's figures
#                      as CI gets them)
#   --tests LIST       only these tests (meson's names)
#   --no-bench         the tests only
#   --no-tests         the benchmarks only
#
# The GPU tests are every test of the build except the CPU-only ones
# (CPU_ONLY below) and the suites that need QEMU, Xvfb, Weston or a soak's
# minutes (vm, display, soak).  Each runs as meson would run it (its
# command, environment and timeout), with ISOTERRA_PLATFORM=device; a
# test's checks are its "N passed, M failed" lines.  The file is written
# after each test ("complete": false until every part has run), so a run
# stopped by a time limit keeps what it ran.  Exit status: 0 when
# every test passed (skips included), 1 when one failed, 2 on bad usage or
# a build that cannot be used.  The driver's own settings pass through:
#   LIBGL_ALWAYS_SOFTWARE=1 MESA_LOADER_DRIVER_OVERRIDE=zink sh tools/gpu-suite.sh
# measures zink on lavapipe (Mesa's GL on Vulkan).
set -u
command -v python3 >/dev/null 2>&1 || { echo "gpu-suite: python3 is needed" >&2; exit 2; }
SRC=$(cd "$(dirname "$0")/.." && pwd)
exec python3 - "$SRC" "$@" <<'PY'
import json, os, platform, re, shutil, signal, subprocess, sys, tempfile, time

SRC = sys.argv[1]
args = sys.argv[2:]
# tests that never open a GL context (pure C: parameters, files, tables,
# flight paths, the hardware layer's decoders, the governor's model, heap counts)
CPU_ONLY = {"params", "io", "mc_tables", "shader_log", "autopilot", "hal", "rotary", "governor", "heap", "soak_judge"}
SKIP_SUITES = {"vm", "display", "soak"}


def usage(msg=None):
    if msg:
        print("gpu-suite: " + msg, file=sys.stderr)
    print("usage: sh tools/gpu-suite.sh [--build DIR] [--out FILE] [--quick] [--device N|PATH]\n"
          "                             [--platform NAME] [--tests NAME,NAME] [--no-bench] [--no-tests]",
          file=sys.stderr)
    sys.exit(2)


opt = {"build": "build", "out": "gpu-suite.json", "quick": False, "device": "", "platform": "device",
       "tests": None, "bench": True, "run_tests": True}
i = 0
while i < len(args):
    a = args[i]
    if a in ("-h", "--help"):
        usage()
    if a == "--quick":
        opt["quick"] = True
    elif a == "--no-bench":
        opt["bench"] = False
    elif a == "--no-tests":
        opt["run_tests"] = False
    elif a in ("--build", "--out", "--device", "--platform", "--tests"):
        if i + 1 >= len(args):
            usage("%s needs a value" % a)
        i += 1
        opt[a[2:]] = args[i]
    else:
        usage("unknown option '%s'" % a)
    i += 1
if opt["tests"] is not None:
    opt["tests"] = [t for t in opt["tests"].split(",") if t]

build = os.path.abspath(opt["build"])
binpath = os.path.join(build, "isoterra")
info_dir = os.path.join(build, "meson-info")
for f in (binpath, os.path.join(info_dir, "intro-tests.json"), os.path.join(info_dir, "meson-info.json")):
    if not os.path.exists(f):
        usage("%s: not a built isoterra tree (no %s)" % (opt["build"], os.path.relpath(f, build)))
out_path = os.path.abspath(opt["out"])

env = dict(os.environ)
env["ISOTERRA_PLATFORM"] = opt["platform"]
if opt["device"]:
    env["ISOTERRA_DEVICE"] = opt["device"]
else:
    env.pop("ISOTERRA_DEVICE", None)
if not env.get("XDG_RUNTIME_DIR"):  # Vulkan's window-system layer warns without one (zink)
    env["XDG_RUNTIME_DIR"] = tempfile.mkdtemp(prefix="gpu-suite-run-")
scratch = tempfile.mkdtemp(prefix="gpu-suite-")
# the program cache and Mesa's shader cache: empty at the start, this run's own
env["XDG_CACHE_HOME"] = os.path.join(scratch, "cache")
env["EGL_LOG_LEVEL"] = env.get("EGL_LOG_LEVEL", "fatal")


def run(cmd, timeout, cwd=None, extra_env=None):
    """(rc or 'timeout', seconds, output, the child's peak RSS in MB)"""
    e = dict(env)
    if extra_env:
        e.update(extra_env)
    t0 = time.monotonic()
    with tempfile.TemporaryFile(dir=scratch) as out:
        try:
            p = subprocess.Popen(cmd, cwd=cwd or build, env=e, stdin=subprocess.DEVNULL, stdout=out,
                                 stderr=subprocess.STDOUT, start_new_session=True)
        except OSError as ex:
            return 127, 0.0, "cannot run %s: %s" % (cmd[0], ex), 0.0
        # reaped here, for the child's own resource usage
        rc, rss = "timeout", 0.0
        while True:
            pid, status, ru = os.wait4(p.pid, os.WNOHANG)
            if pid == p.pid:
                rc = os.waitstatus_to_exitcode(status)
                rss = ru.ru_maxrss / 1024.0
                break
            if time.monotonic() - t0 > timeout:
                os.killpg(p.pid, signal.SIGKILL)
                os.wait4(p.pid, 0)
                break
            time.sleep(0.02)
        p.returncode = rc if rc != "timeout" else -9
        secs = time.monotonic() - t0
        out.seek(0)
        return rc, secs, out.read().decode("utf-8", "replace"), rss


def read(path):
    try:
        with open(path, encoding="utf-8", errors="replace") as f:
            return f.read()
    except OSError:
        return ""


# ---- the machine
def machine():
    m = {"host": platform.node(), "kernel": " ".join(platform.uname()[i] for i in (0, 2, 4)),
         "cores": os.cpu_count()}
    cpu = re.search(r"^model name\s*:\s*(.*)$", read("/proc/cpuinfo"), re.M)
    m["cpu"] = cpu.group(1).strip() if cpu else platform.processor()
    mem = re.search(r"^MemTotal:\s*(\d+) kB", read("/proc/meminfo"), re.M)
    m["memory_gib"] = round(int(mem.group(1)) / 1048576, 1) if mem else None
    osr = re.search(r'^PRETTY_NAME="?([^"\n]*)', read("/etc/os-release"), re.M)
    m["os"] = osr.group(1) if osr else None
    m["load_average"] = [round(x, 2) for x in os.getloadavg()]
    # the kernel's DRM drivers (render nodes) and, on NVIDIA, nvidia-smi's view
    drm = {}
    if os.path.isdir("/sys/class/drm"):
        for n in sorted(os.listdir("/sys/class/drm")):
            if n.startswith("renderD"):
                drv = os.path.join("/sys/class/drm", n, "device", "driver")
                drm["/dev/dri/" + n] = os.path.basename(os.path.realpath(drv)) if os.path.exists(drv) else None
    m["drm_render_nodes"] = drm
    if shutil.which("nvidia-smi"):
        rc, _, o, _ = run(["nvidia-smi", "--query-gpu=name,driver_version,memory.total", "--format=csv,noheader"], 30)
        if rc == 0:
            m["nvidia_smi"] = [l.strip() for l in o.splitlines() if l.strip()]
    return m


# ---- the EGL device and its GL
def gl_info():
    g = {"platform": opt["platform"], "device": opt["device"] or None}
    rc, _, lst, _ = run([binpath, "--list-devices"], 120)
    g["devices"] = lst.rstrip().splitlines()
    res = os.path.join(scratch, "gl.json")
    cmd = [binpath, "--platform", opt["platform"], "--size", "64x48", "--grid", "16", "--out",
           os.path.join(scratch, "gl.png"), "--results", res, "--verbose"]
    rc, _, log, _ = run(cmd, 300)
    try:
        r = json.load(open(res))
        g["renderer"] = r["gl"]["renderer"]
        g["version"] = r["gl"]["version"]
    except (OSError, ValueError, KeyError):
        g["error"] = "isoterra --platform %s failed (%s): %s" % (opt["platform"], rc, log.strip()[-400:])
        return g
    mm = re.search(r"EGL (\d+\.\d+), vendor '([^']*)'", log)
    if mm:
        g["egl_version"], g["egl_vendor"] = mm.group(1), mm.group(2)
    mm = re.search(r"EGL device (\d+) of \d+(?: (/\S+))?", log)
    if mm:
        g["device_index"] = int(mm.group(1))
        g["drm_node"] = mm.group(2)
        # that device's block of the list: its kind, EGL driver, extensions
        block, on = [], False
        for l in g["devices"]:
            if re.match(r"^\d+: ", l):
                on = l.startswith("%d: " % g["device_index"])
            if on:
                block.append(l)
        if block:
            g["device_kind"] = block[0].split(": ", 1)[1].split(",")[0]
            for l in block:
                d = re.match(r"^\s+EGL: vendor .*?, driver (\S+)", l)
                if d:
                    g["egl_driver"] = d.group(1)
                if l.strip().startswith("extensions:"):
                    g["device_extensions"] = l.split(":", 1)[1].split()
    # the driver: Mesa's gallium driver (EGL_MESA_query_driver), else the
    # vendor's version string
    ver = g["version"]
    mesa = re.search(r"Mesa (\S+)", ver)
    if mesa:
        g["driver"] = "Mesa %s, EGL driver %s" % (mesa.group(1), g.get("egl_driver") or "unknown")
    else:
        g["driver"] = re.sub(r"^OpenGL ES \d+\.\d+ ?", "", ver) or ver
    return g


# ---- the tests
def tests():
    meta = json.load(open(os.path.join(info_dir, "meson-info.json")))
    old_src = meta["directories"]["source"].rstrip("/")
    old_build = meta["directories"]["build"].rstrip("/")

    def move(s):
        if not isinstance(s, str):
            return s
        for old, new in ((old_build, build), (old_src, SRC)):
            if s == old or s.startswith(old + "/"):
                return new + s[len(old):]
            s = s.replace("=" + old + "/", "=" + new + "/")
        return s

    rows = []
    for t in json.load(open(os.path.join(info_dir, "intro-tests.json"))):
        name = t["name"]
        suites = {s.split(":")[-1] for s in t.get("suite", [])}
        if opt["tests"] is not None:
            if name not in opt["tests"]:
                continue
        elif name in CPU_ONLY or suites & SKIP_SUITES or (opt["quick"] and "gallery" in suites):
            continue
        cmd = [move(c) for c in t["cmd"]]
        tenv = {k: move(v) for k, v in (t.get("env") or {}).items()}
        # the platform under test wins over a test's own default
        tenv.pop("ISOTERRA_PLATFORM", None)
        timeout = t.get("timeout") or 600
        print("gpu-suite: test %s ..." % name, end="", flush=True)
        rc, secs, output, _ = run(cmd, timeout, cwd=move(t.get("workdir")) or build, extra_env=tenv)
        counts = re.findall(r"(\d+) passed, (\d+) failed", output)
        passed = sum(int(p) for p, _ in counts)
        failed = sum(int(f) for _, f in counts)
        result = "TIMEOUT" if rc == "timeout" else "SKIP" if rc == 77 else "OK" if rc == 0 else "FAIL"
        row = {"name": name, "result": result, "rc": rc, "seconds": round(secs, 1), "passed": passed,
               "failed": failed}
        if result not in ("OK", "SKIP"):
            row["tail"] = output.rstrip().splitlines()[-30:]
        gl = re.search(r"^GL: (.*)$", output, re.M)
        if gl:
            row["gl"] = gl.group(1)
        rows.append(row)
        print(" %s %.1f s, %d passed, %d failed" % (result, secs, passed, failed), flush=True)
        doc["tests"] = rows
        save()  # a run stopped later keeps what it ran
    return rows


# ---- the benchmarks
def num(pattern, text, group=1, flags=re.M):
    m = re.search(pattern, text, flags)
    return float(m.group(group)) if m else None


def bench_pipeline():
    exe = os.path.join(build, "bench", "bench_pipeline")
    cmd = [exe, "--no-peers"] + (["--quick", "--sizes", "64,128"] if opt["quick"] else ["--sizes", "64,128,256"])
    cmd += ["--", "--platform", opt["platform"]]
    rc, secs, o, _ = run(cmd, 1800)
    b = {"cmd": " ".join(["bench/bench_pipeline"] + cmd[1:]), "rc": rc, "seconds": round(secs, 1)}
    f = {}
    passes = {}
    for name in ("density", "classify", r"pyramid \(reduce\+setup\)", "vertices", "indices", r"whole run \(wall\)"):
        mm = re.search(r"^  %s\s+([\d.]+) \[" % name, o, re.M)
        if mm:
            passes[re.sub(r"\\", "", name)] = float(mm.group(1))
    f["grid128_pass_ms_median"] = passes
    f["grid128_whole_pipeline_ms"] = num(r"^  whole pipeline, AO\+sun as given\s+([\d.]+)", o)
    f["grid128_density_pass_ms"] = num(r"^  density pass alone\s+([\d.]+)", o)
    sizes = {}
    for mm in re.finditer(r"^grid (\d+) \(the flags' field and AO\).*?\n(.*?)(?=^grid \d+ \(the flags|^compaction|\Z)",
                          o, re.M | re.S):
        body = mm.group(2)
        w = re.search(r"^  whole pipeline\s+([\d.]+) \[", body, re.M)
        r = re.search(r"([\d.]+) Mvoxels/s, ([\d.]+) Mtriangles/s", body)
        sizes[mm.group(1)] = {"whole_ms": float(w.group(1)) if w else None,
                              "mvoxels_s": float(r.group(1)) if r else None,
                              "mtriangles_s": float(r.group(2)) if r else None}
    f["grids"] = sizes
    comp = {}
    for mm in re.finditer(r"^grid (\d+), whole runs[^\n]*\n(.*?)(?:\n\s*\n|\Z)", o, re.M | re.S):
        rows = {}
        for r in re.finditer(r"^  (HistoPyramid|atomic append|none) \([^)]*\)\s+([\d.]+|n/a)", mm.group(2), re.M):
            rows[r.group(1)] = None if r.group(2) == "n/a" else float(r.group(2))
        comp[mm.group(1)] = rows
    f["compaction_whole_ms_by_grid"] = comp
    f["machine_line"] = (re.search(r"^machine: (.*)$", o, re.M) or [None, None])[1]
    b["figures"] = f
    b["output"] = o.rstrip().splitlines()
    return b


def bench_world():
    exe = os.path.join(build, "bench", "bench_world")
    # the program's own runs are timed below, on the same platform
    cmd = [exe, "--no-program", "--platform", opt["platform"]] + (["--quick"] if opt["quick"] else [])
    rc, secs, o, _ = run(cmd, 1800)
    b = {"cmd": " ".join(["bench/bench_world"] + cmd[1:]), "rc": rc, "seconds": round(secs, 1)}
    f = {"blocks_per_s_without_ao": num(r"^  without AO\s+([\d.]+) blocks/s", o),
         "blocks_per_s_with_ao": num(r"^  with AO\s+([\d.]+) blocks/s", o)}
    fill = re.search(r"in (\d+) ms wall, (\d+) ms CPU: ([\d.]+) blocks/s settled, ([\d.]+) generated/s", o)
    if fill:
        f["fill_first_view"] = {"wall_ms": float(fill.group(1)), "cpu_ms": float(fill.group(2)),
                                "settled_per_s": float(fill.group(3)), "generated_per_s": float(fill.group(4))}
    fly = {}
    for mm in re.finditer(r"^  (full|governed)\s+(\d+x\d+)\s+(\d+) frames\s+p50\s+([\d.]+) ms.*?p95\s+([\d.]+)"
                          r"\s+p99\s+([\d.]+)\s+max\s+([\d.]+)", o, re.M):
        fly["%s %s" % (mm.group(1), mm.group(2))] = {"frames": int(mm.group(3)), "p50_ms": float(mm.group(4)),
                                                    "p95_ms": float(mm.group(5)), "p99_ms": float(mm.group(6)),
                                                    "max_ms": float(mm.group(7))}
    f["peak_rss_mb"] = num(r"^peak RSS of this benchmark process: ([\d.]+) MB", o)
    f["flythrough"] = fly
    b["figures"] = f
    b["output"] = o.rstrip().splitlines()
    return b


def program_runs():
    """the program as a user runs it on this platform: the no-flag picture
    (caches empty, then warm) and the world's first 30 frames at 640x360"""
    n = 1 if opt["quick"] else 3
    p = {"runs": n}
    base = [binpath, "--platform", opt["platform"]]
    cold, warm, rss = [], [], []
    # the warm cache filled first
    run(base + ["--out", os.path.join(scratch, "p.png")], 600, extra_env={"XDG_CACHE_HOME": os.path.join(scratch, "w")})
    for k in range(n):
        for which, lst in (("cold", cold), ("warm", warm)):
            cache = os.path.join(scratch, "c%d" % k if which == "cold" else "w")
            rc, secs, o, mb = run(base + ["--out", os.path.join(scratch, "p.png")], 600,
                                  extra_env={"XDG_CACHE_HOME": cache})
            if rc != 0:
                p["error"] = o.strip()[-400:]
                return p
            lst.append(round(secs * 1000))
            rss.append(mb)
    p["no_flags_ms_caches_empty"] = sorted(cold)[n // 2]
    p["no_flags_ms_caches_warm"] = sorted(warm)[n // 2]
    p["no_flags_peak_rss_mb"] = round(sorted(rss)[n], 1)
    res = os.path.join(scratch, "world.json")
    rc, secs, o, mb = run(base + ["--scene", "world", "--count", "30", "--size", "640x360", "--out",
                                  os.path.join(scratch, "w.png"), "--results", res], 900,
                          extra_env={"XDG_CACHE_HOME": os.path.join(scratch, "w")})
    try:
        r = json.load(open(res))
        p["world_30_frames_640x360"] = {"wall_s": round(secs, 2), "first_frame_ms": r["run"]["first_frame_ms"],
                                        "frame_ms": r["frame_ms"], "peak_rss_mb": round(mb, 1)}
    except (OSError, ValueError, KeyError):
        p["world_error"] = o.strip()[-400:]
    return p


def commit():
    if not shutil.which("git"):
        return None
    try:
        return subprocess.run(["git", "-C", SRC, "rev-parse", "--short", "HEAD"], capture_output=True, text=True,
                              timeout=10).stdout.strip() or None
    except (OSError, subprocess.SubprocessError):
        return None


def save():
    """the results so far, written whole (a temporary file, then renamed)"""
    tmp = out_path + ".tmp"
    with open(tmp, "w", encoding="utf-8") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")
    os.replace(tmp, out_path)


t_start = time.time()
doc = {"suite": "isoterra tools/gpu-suite.sh", "format": 1,
       "date": time.strftime("%Y-%m-%dT%H:%M:%S%z", time.localtime(t_start)), "commit": commit(),
       "build": build, "options": {k: v for k, v in opt.items() if k != "build"},
       "driver_env": {k: os.environ[k] for k in sorted(os.environ)
                      if k.startswith(("MESA_", "LIBGL_", "GALLIUM_", "__GL", "VK_", "ISOTERRA_"))}}
doc["complete"] = False  # true once every part has run
doc["machine"] = machine()
doc["gl"] = gl_info()
print("gpu-suite: %s | %s (%s)" % (doc["gl"].get("renderer"), doc["gl"].get("version"), doc["gl"].get("driver")),
      flush=True)
doc["tests"] = tests() if opt["run_tests"] else []
tot = {"tests": len(doc["tests"])}
for r in ("OK", "FAIL", "TIMEOUT", "SKIP"):
    tot[r.lower()] = sum(1 for t in doc["tests"] if t["result"] == r)
tot["checks_passed"] = sum(t["passed"] for t in doc["tests"])
tot["checks_failed"] = sum(t["failed"] for t in doc["tests"])
doc["totals"] = tot
if opt["bench"]:
    print("gpu-suite: bench_pipeline ...", flush=True)
    doc["bench_pipeline"] = bench_pipeline()
    print("gpu-suite: bench_world ...", flush=True)
    doc["bench_world"] = bench_world()
    print("gpu-suite: the program ...", flush=True)
    doc["program"] = program_runs()
doc["seconds"] = round(time.time() - t_start, 1)
doc["machine"]["load_average_end"] = [round(x, 2) for x in os.getloadavg()]
doc["complete"] = True
save()
shutil.rmtree(scratch, ignore_errors=True)
failed = [t["name"] for t in doc["tests"] if t["result"] in ("FAIL", "TIMEOUT")]
print("gpu-suite: %d tests: %d ok, %d failed, %d skipped; checks %d passed, %d failed -> %s" %
      (tot["tests"], tot["ok"], tot["fail"] + tot["timeout"], tot["skip"], tot["checks_passed"], tot["checks_failed"],
       out_path))
if failed:
    print("gpu-suite: failed: " + " ".join(failed))
sys.exit(1 if failed else 0)
PY
