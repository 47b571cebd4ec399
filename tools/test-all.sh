#!/bin/sh
# isoterra — the whole test suite: a -Werror build and its tests, then the
# same tests built with AddressSanitizer + UndefinedBehaviorSanitizer, then
# Debian 13, arm64 and the Debian package in chroots (as root).
# GPU tests run on Mesa's llvmpipe through EGL_MESA_platform_surfaceless
# unless ISOTERRA_PLATFORM names another backend.
set -u
cd "$(dirname "$0")/.." || exit 2
total_pass=0
total_fail=0
failures=$(mktemp)
timings=$(mktemp)
trap 'rm -f "$failures" "$timings"' EXIT
# the wall time of each part, printed at the end (CI's budget is 45 minutes)
t_begin=$(date +%s)
t_last=$t_begin
part_done() { # NAME: the time since the previous part ended
	now=$(date +%s)
	printf '  %-44s %5d s\n' "$1" $((now - t_last)) >>"$timings"
	t_last=$now
}

run_suite() { # name builddir meson-args...
	name=$1
	dir=$2
	shift 2
	echo "=== $name: configure ($*)"
	if [ ! -d "$dir" ]; then
		if ! meson setup "$dir" "$@" >"$dir.setup.log" 2>&1; then
			cat "$dir.setup.log"
			total_fail=$((total_fail + 1))
			echo "--- $name: meson setup failed (its log is above)" >>"$failures"
			return 1
		fi
	fi
	echo "=== $name: build"
	if ! ninja -C "$dir"; then
		# counted and named at the end like a failed test
		total_fail=$((total_fail + 1))
		echo "--- $name: the build failed (ninja -C $dir; its error is above)" >>"$failures"
		part_done "$name: configure, build"
		return 1
	fi
	part_done "$name: configure, build"
	# shellcheck disable=SC2086 # TEST_ARGS is a word list on purpose
	run_tests "$name" "$dir" testlog $TEST_ARGS
	rc=$?
	part_done "$name: tests"
	return $rc
}

run_tests() { # name builddir logbase meson-test-args...: the tests of a built tree, counted
	name=$1
	dir=$2
	logbase=$3
	shift 3
	echo "=== $name: test"
	# two at a time: the tests that judge time run alone all the same
	# (is_parallel false in tests/meson.build)
	meson test -C "$dir" --print-errorlogs --num-processes 2 --logbase "$logbase" "$@"
	count_tests "$name" "$dir" "$logbase" $?
}

count_tests() { # name builddir logbase meson-exit-status: counts a finished meson test run
	name=$1
	dir=$2
	logbase=$3
	rc=$4
	# count the individual checks the test programs report
	p=$(grep -hoE '[0-9]+ passed, [0-9]+ failed' "$dir/meson-logs/$logbase.txt" | awk '{s+=$1} END {print s+0}')
	f=$(grep -hoE '[0-9]+ passed, [0-9]+ failed' "$dir/meson-logs/$logbase.txt" | awk '{s+=$3} END {print s+0}')
	total_pass=$((total_pass + p))
	total_fail=$((total_fail + f))
	[ $rc -eq 0 ] || total_fail=$((total_fail + 1))
	# the failed tests by name, with the end of what each printed, again
	# at the very end (a CI log is often read from its tail)
	python3 - "$dir/meson-logs/$logbase.json" "$name" >>"$failures" <<'PY' || true
import json, sys
for line in open(sys.argv[1], encoding="utf-8", errors="replace"):
    try:
        t = json.loads(line)
    except ValueError:
        continue
    if t.get("result") not in ("OK", "SKIP", "EXPECTEDFAIL"):
        print("--- %s: %s %s (%.0f s)" % (sys.argv[2], t.get("name"), t.get("result"), t.get("duration", 0)))
        out = ((t.get("stdout") or "") + (t.get("stderr") or "")).rstrip().splitlines()
        for l in out[-15:]:
            print("    " + l)
PY
	return $rc
}

# the display and VM tests (Xvfb, Weston, QEMU) fail rather than skip when a tool
# is missing: tools/deps.sh installs them all
export ISOTERRA_REQUIRE_DEVICE_TESTS=1
status=0

# The Debian 13 suites (at the end, as root) first make their chroots:
# debootstrap, apt-get install of the build dependencies, GDAL's for the
# package, the arm64 cross toolchain, the bookworm base: about 7 minutes
# of downloads and unpacking on a fresh machine, mostly waiting on the
# network and the disk.  They are started now, in the background, while
# the host's builds and tests keep the CPUs busy; each script's lock
# (tools/chroot.sh) makes the suites wait for them later.  Their output:
# build-d13/logs/prepare.log, summed up before the suites run.  At nice 10:
# the tests beside them keep the CPUs they need (a VM test's guest held off
# by the host loses GPIO edges), the chroots take what is left.
chroot_suites=0
AS_ROOT=""
if [ "${ISOTERRA_SKIP_CHROOT_SUITES:-0}" != 1 ]; then
	if [ "$(id -u)" -eq 0 ]; then
		chroot_suites=1
	elif command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
		chroot_suites=1
		AS_ROOT="sudo -n"
	fi
fi
prepare_pid=""
if [ $chroot_suites = 1 ]; then
	mkdir -p build-d13/logs
	(
		for s in debian13 arm64 debpkg; do
			t=$(date +%s)
			$AS_ROOT nice -n 10 sh "tools/$s.sh" prepare
			echo "== prepare $s: exit $?, $(($(date +%s) - t)) s"
		done
	) >build-d13/logs/prepare.log 2>&1 </dev/null &
	prepare_pid=$!
fi
# Tests that boot a kernel under QEMU (meson suite "vm"), the soak (suite
# "soak"), the gallery's pictures, the wall's stitched tiles (suite
# "pictures") and the folder walls (suite "structure") run once, against
# the release build;
# the sanitizer build runs everything else.  The soak runs later, beside
# the fuzzers, and the VM tests after them, once the chroots are made (see
# there).
TEST_ARGS="--no-suite soak --no-suite vm"
run_suite "release (-Werror)" build-ci -Dwerror=true -Dbuildtype=debugoptimized || status=1

# A second driver: zink on lavapipe (Mesa's OpenGL on Vulkan, package
# mesa-vulkan-drivers; without LIBGL_ALWAYS_SOFTWARE=1 eglInitialize
# fails), the release build's GPU tests again, not rebuilt (meson's logs:
# build-ci/meson-logs/zink.*).  Measured one by one under zink on this
# 2-core machine (debugoptimized, load 2-3), seconds: platform 1,
# density 14, histopyramid 3, pipeline 32, parts 7, render 5, world 47,
# world_pool 18, debris 2, yuv 5, curves 12, scene_grid 2, shader_watch 2,
# platform_no_es31 1, cli 8, outputs 19, curves_cli 17, hal_cli 5,
# notify 5, gl_limits 17, gl_limits_cli 51, program_cache 2,
# render_scale 1, cull 1, antialias 2, results 6, devices 4 (13 at load
# 5), gallery 124 (load 5), probe 6 (44 at load 10): about 7.5 minutes
# in all, every one passing (yuv's paced sink drops frames under zink
# when the machine is loaded, 4 runs of 10 at a load average of 9-10,
# none at 2: docs/PLATFORMS.md, "Measured per driver").  Left out:
# rss_world (it skips there: its 185 MiB ceiling's model is a driver
# whose own floor fits 109.5 MiB, docs/RELIABILITY.md; zink on lavapipe's
# is 128-135 MiB), kiosk (97 s at load 10, 66 on llvmpipe: the program's reloads and
# playlists, not the driver; over the ~8 minutes this suite may take),
# the CPU-only tests (params, io, mc_tables, shader_log, autopilot, hal,
# rotary, governor, heap: no GL, the same under any driver; autopilot
# alone is 100 s) and the display, VM and soak suites (the release suite
# runs them once).
# Kept to the tests of the GL itself (about 3.5 minutes): the command-line
# suites that exercise the program's options more than the driver
# (gallery 124 s, gl_limits_cli 51, outputs 19, curves_cli 17, cli 8,
# hal_cli 5, results 6: they passed under zink when measured) run on
# llvmpipe only, for the CI's 45-minute budget; so do world_pool (18 s
# under zink: the pool's bookkeeping, which world exercises there) and
# notify (5 s: sd_notify, no GL).
ZINK_TESTS="platform density histopyramid pipeline parts render world world_terms debris shadows shading yuv curves scene_grid scene_capacity
	shader_watch platform_no_es31 gl_limits program_cache render_scale cull antialias devices probe"
if [ -x build-ci/isoterra ]; then
	# only the tests this build has (notify needs libsystemd, curves GDAL)
	have=$(meson test -C build-ci --no-rebuild --list 2>/dev/null | sed -n 's|^isoterra[^ ]* / ||p')
	zink_list=""
	for t in $ZINK_TESTS; do
		echo "$have" | grep -qx "$t" && zink_list="$zink_list $t"
	done
	export LIBGL_ALWAYS_SOFTWARE=1 MESA_LOADER_DRIVER_OVERRIDE=zink
	# lavapipe's window-system layer warns on every start without one
	zink_xdg=""
	if [ -z "${XDG_RUNTIME_DIR:-}" ]; then
		zink_xdg=$(mktemp -d)
		export XDG_RUNTIME_DIR="$zink_xdg"
	fi
	# the tests must really run on zink (a missing Vulkan driver would
	# fall back or fail in every test alike): say so once, as a failure
	if [ -z "$zink_list" ]; then
		echo "=== zink: none of the tests is in build-ci"
		total_fail=$((total_fail + 1))
		echo "--- zink: none of the tests is in build-ci" >>"$failures"
		status=1
	elif build-ci/isoterra --list-devices 2>&1 | grep -q 'driver zink'; then
		# shellcheck disable=SC2086 # the list is a word list
		run_tests "zink (release build on Mesa's GL on Vulkan)" build-ci zink --no-rebuild $zink_list || status=1
	else
		echo "=== zink: Mesa's zink driver does not load (install mesa-vulkan-drivers: tools/deps.sh)"
		build-ci/isoterra --list-devices
		total_fail=$((total_fail + 1))
		echo "--- zink: the zink driver does not load (mesa-vulkan-drivers, tools/deps.sh)" >>"$failures"
		status=1
	fi
	unset LIBGL_ALWAYS_SOFTWARE MESA_LOADER_DRIVER_OVERRIDE
	[ -z "$zink_xdg" ] || { rm -rf "$zink_xdg"; unset XDG_RUNTIME_DIR; }
fi
part_done "zink: tests"
# The X11 display test (suite "x11") runs in the release build only: under
# the sanitizers its windowed frames take over a second each (llvmpipe's
# X11 presentation beside the instrumented program; 188 s against 70 in
# the last CI run, alone, as it must run), the longest single item of the
# sanitizer suite; the Wayland display test, the same display sink and
# frame loop, stays.
TEST_ARGS="--no-suite vm --no-suite gallery --no-suite pictures --no-suite structure --no-suite x11 --no-suite soak"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1"
export LSAN_OPTIONS="suppressions=$(pwd)/tests/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
# Mesa's driver (22.3.6-1+deb12u2) keeps what a pthread_once initializer
# allocates and is unloaded by eglTerminate: at exit LeakSanitizer finds
# that memory unreferenced, allocated from an "<unknown module>" that no
# suppression can name (the frame-pointer unwind stops in the driver; a
# full unwind per allocation makes the suite many times slower).  Loaded
# before the program, the driver stays mapped to the end, and its data is
# reachable again; isoterra's own leaks are still reported.
old_preload=${LD_PRELOAD:-}
for d in /usr/lib/*/dri /usr/lib/dri; do
	if [ -f "$d/swrast_dri.so" ]; then
		export LD_PRELOAD="$d/swrast_dri.so${old_preload:+ $old_preload}"
		ASAN_OPTIONS="$ASAN_OPTIONS:verify_asan_link_order=0"
		break
	fi
done
run_suite "ASan+UBSan" build-asan -Dwerror=true -Dbuildtype=debugoptimized -Db_sanitize=address,undefined \
	-Db_lundef=false -Dc_args=-fno-sanitize-recover=all || status=1
if [ -n "$old_preload" ]; then export LD_PRELOAD="$old_preload"; else unset LD_PRELOAD; fi

# the libFuzzer harnesses (tests/fuzz/, docs/RELIABILITY.md): 60 s each under
# ASan+UBSan, built with clang in build-fuzz/ (tools/fuzz.sh)
# (30 s each, two at a time on 2 cores: the harnesses replay their seeds
# and every input that once failed, then search briefly; long searches are
# for `sh tools/fuzz.sh 3600`, docs/RELIABILITY.md)
fuzz_secs=${ISOTERRA_FUZZ_SECONDS:-30}
# The soak suite of the release build runs beside them: both run for a
# set time, not a set amount of work (the soak 3 minutes of the world,
# judged on its resident memory, not its speed; soak_judge its own
# children side by side; the fuzzers 30 s each), so side by side they take
# the time of the longer, not the sum.  Its log: build-ci/meson-logs/soak.*
soak_pid=""
if [ -x build-ci/isoterra ]; then
	meson test -C build-ci --no-rebuild --print-errorlogs --num-processes 2 --logbase soak --suite soak \
		>build-ci/soak.out 2>&1 </dev/null &
	soak_pid=$!
fi
echo "=== fuzz: tests/fuzz, $fuzz_secs s per harness (clang, ASan+UBSan)"
fuzz_log=$(mktemp)
sh tools/fuzz.sh "$fuzz_secs" >"$fuzz_log" 2>&1
rc=$?
cat "$fuzz_log"
line=$(grep -E '^== fuzz: [0-9]+ passed, [0-9]+ failed' "$fuzz_log" | tail -1)
rm -f "$fuzz_log"
total_pass=$((total_pass + $(echo "$line" | awk '{print $3+0}')))
total_fail=$((total_fail + $(echo "$line" | awk '{print $5+0}')))
[ -n "$line" ] || total_fail=$((total_fail + 1))
[ $rc -eq 0 ] || status=1
part_done "fuzz: build, ${fuzz_secs} s per harness"
if [ -n "$soak_pid" ]; then
	wait "$soak_pid"
	rc=$?
	echo "=== soak (release build, beside the fuzzers): test"
	cat build-ci/soak.out
	count_tests "soak" build-ci soak $rc || status=1
	part_done "soak: the rest after the fuzzers"
fi

# The release build's VM tests (suite "vm": GPIO, V4L2 and KMS in a kernel
# under QEMU, one at a time), on a machine left to them: the chroots are
# made first.  A guest emulated by TCG is slowed far more than the host's
# own tests by the chroots' unpacking beside it (the GPIO test took 257 s
# beside it in a CI run here, 106 s alone; the V4L2 test 292 s).
if [ -n "$prepare_pid" ]; then
	wait "$prepare_pid"
	prepare_pid=""
	part_done "(waiting for the chroots, before the VM tests)"
fi
if [ -x build-ci/isoterra ]; then
	run_tests "VM tests (release build)" build-ci vm --no-rebuild --suite vm || status=1
	part_done "VM tests (release build)"
fi

# Debian 13 (trixie) in a chroot, as root (tools/chroot.sh; cached in
# build-d13/): the tests with Mesa 25 and GCC 14, the arm64 cross build run
# under qemu-user, the Debian package built, linted and installed.  Each
# script ends with "== debian13 NAME: P passed, F failed".
# ISOTERRA_SKIP_CHROOT_SUITES=1 leaves them out (say, without root).
run_chroot_suite() { # title script
	echo "=== $1"
	mkdir -p build-d13/logs
	log=build-d13/logs/suite-$2.log
	{ $AS_ROOT sh "tools/$2.sh"; echo $? >"$log.rc"; } 2>&1 | tee "$log"
	part_done "$1"
	rc=$(cat "$log.rc" 2>/dev/null || echo 1)
	line=$(grep -E '^== debian13 [a-z0-9]+: [0-9]+ passed, [0-9]+ failed' "$log" | tail -1)
	p=$(echo "$line" | awk '{print $4+0}')
	f=$(echo "$line" | awk '{print $6+0}')
	[ -n "$line" ] || f=1
	total_pass=$((total_pass + p))
	total_fail=$((total_fail + f))
	[ "$rc" -eq 0 ] || { [ "$f" -gt 0 ] || total_fail=$((total_fail + 1)); return 1; }
}
if [ "${ISOTERRA_SKIP_CHROOT_SUITES:-0}" != 1 ]; then
	if [ $chroot_suites = 0 ]; then
		echo "=== Debian 13 suites: need root (run as root, or ISOTERRA_SKIP_CHROOT_SUITES=1)"
		total_fail=$((total_fail + 1))
		status=1
	else
		echo "=== Debian 13 chroots, made in the background (build-d13/logs/prepare.log)"
		if [ -n "$prepare_pid" ]; then
			wait "$prepare_pid"
		fi
		grep -E '^(== prepare|\[[0-9:]+\] (FAIL|chroot ready|package suite prepared))' build-d13/logs/prepare.log
		part_done "(waiting for the chroots)"
		# the package build runs no tests by default here: the Debian 13
		# suite ran them on the same sources with trixie's compiler and Mesa
		ISOTERRA_DEB_NOCHECK=${ISOTERRA_DEB_NOCHECK:-1}
		export ISOTERRA_DEB_NOCHECK
		run_chroot_suite "Debian 13 (chroot): build -Werror, tests" debian13 || status=1
		run_chroot_suite "arm64: the packages cross-built, qemu-user smoke run" arm64 || status=1
		run_chroot_suite "Debian package: build, lintian, install" debpkg || status=1
	fi
fi
if [ -s "$failures" ]; then
	echo "=== failed tests"
	cat "$failures"
fi
echo "=== wall time of each part"
cat "$timings"
echo "  total: $(($(date +%s) - t_begin)) s"
echo "all suites: $total_pass passed, $total_fail failed"
exit $status
