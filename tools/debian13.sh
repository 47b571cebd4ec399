#!/bin/sh
# isoterra — the test suite on Debian 13 (trixie: Mesa 25, GCC 14, meson
# 1.7, libgpiod 2) in a minbase chroot, from Debian's archive.  As root:
#
#   sh tools/debian13.sh          build (-Werror) and run the tests there
#   sh tools/debian13.sh clean    drop the cached chroots (build-d13/)
#   sh tools/debian13.sh prepare  only make the chroot and its packages
#                                 ready (tools/test-all.sh runs this in the
#                                 background while the host's suites build)
#
# The chroot, its packages and the build folder are cached in build-d13/
# (tools/chroot.sh) and reused when present: a warm run rebuilds only what
# changed.  Tests that need a display server (suite display) stay on the
# Debian 12 host, and so do the VM tests (suite vm) but one: see below;
# everything else runs here.
# Ends with "== debian13 native: N passed, M failed" (tools/test-all.sh
# adds it to its totals); exit status 0 when all passed.
set -u
. "$(dirname "$0")/chroot.sh"

# ---- the hal on libgpiod 2 ----------------------------------------------
# Debian 13 has libgpiod 2.2: the build must have the GPIO knobs on the
# hal's libgpiod-2 backend (hal/gpiod_v2.c; checked), -Werror whole, and
# hal_cli runs with the other tests.  With ISOTERRA_D13_HAL_GPIOD2=1 (the
# default) the gpio-sim test (tests/vm/gpio_knobs.sh) also runs once with
# this build: from the host, whose QEMU boots the host's Debian 12 kernel
# with gpio-sim built from its linux-source-6.1 as for the host's own run,
# and the guest runs this chroot's isoterra and hal_probe in a chroot of
# build-d13/root (the guest sees the host's / over 9p), so libgpiod 2 meets
# the real kernel driver.  Its checks count in this suite's totals.
# ISOTERRA_D13_HAL_GPIOD2=0 leaves that run out (~3 min, or where the host
# has no QEMU).
HAL_GPIOD2=${ISOTERRA_D13_HAL_GPIOD2:-1}

# the build dependencies of tools/deps.sh, Debian 13 names
PACKAGES="gcc libc6-dev meson ninja-build pkgconf libegl-dev libgles-dev libpng-dev libexpat1-dev
	libegl-mesa0 libgbm-dev libdrm-dev libgpiod-dev
	libwayland-dev wayland-protocols libx11-dev libx11-xcb-dev libxcb1-dev libxcb-shm0-dev libsystemd-dev libudev-dev"

if [ "${1:-}" = clean ]; then
	d13_need_root "$@"
	d13_lock
	d13_rm "$D13" && echo "removed $D13"
	exit $?
fi
d13_need_root "$@"
d13_lock
t0=$(date +%s)
B=/build/native

d13_root || { d13_bad "Debian 13 chroot"; d13_summary native; exit 1; }
d13_mount "$D13_ROOT" || { d13_bad "mounts"; d13_summary native; exit 1; }
# shellcheck disable=SC2086 # word lists
d13_install "$D13_ROOT" $PACKAGES || { d13_bad "build dependencies"; d13_summary native; exit 1; }
d13_log "chroot ready ($(($(date +%s) - t0)) s): $(d13_in "$D13_ROOT" dpkg-query -W -f '${Package} ${Version}, ' \
	libegl-mesa0 libgpiod-dev gcc-14 meson 2>/dev/null)"
if [ "${1:-}" = prepare ]; then
	echo "== debian13 prepare: ok"
	exit 0
fi
d13_copy_src "$D13_ROOT" || { d13_bad "source copy"; d13_summary native; exit 1; }

# configure once, later only set the options (the build stays incremental)
t1=$(date +%s)
setup="setup $B /src"
[ -f "$D13_ROOT$B/build.ninja" ] && setup="configure $B"
# shellcheck disable=SC2086 # a word list
d13_in "$D13_ROOT" meson $setup -Dwerror=true -Dbuildtype=debugoptimized -Dc_args= \
	>"$D13_LOGS/native-setup.log" 2>&1 ||
	{ cat "$D13_LOGS/native-setup.log"; d13_bad "meson $setup"; d13_summary native; exit 1; }
if d13_in "$D13_ROOT" ninja -C "$B" >"$D13_LOGS/native-build.log" 2>&1; then
	d13_ok "-Werror build with $(d13_in "$D13_ROOT" gcc -dumpfullversion) ($(($(date +%s) - t1)) s)"
else
	tail -40 "$D13_LOGS/native-build.log"
	d13_bad "build"
	d13_summary native
	exit 1
fi
gpiod=$(grep -o "GPIO knobs: libgpiod [^ ]*, API v[0-9]" "$D13_ROOT$B/meson-logs/meson-log.txt" | tail -1)
case "$gpiod" in
*"API v2") d13_ok "${gpiod#GPIO knobs: } (hal/gpiod_v2.c)" ;;
*) d13_bad "the GPIO knobs are not on libgpiod 2: '${gpiod:-built out}'" ;;
esac

t1=$(date +%s)
# every test of the suites but vm, display, soak, gallery, pictures and
# structure (the plain build of tools/test-all.sh runs the VM tests, the
# soak, the README's pictures, the wall's stitched tiles and the folder
# walls once; the VM test that needs Debian 13's libgpiod 2 runs below),
# and but autopilot: 168
# flights of plain C over the CPU density, no GL, no library of trixie's
# (80 s of CPU; the host's release and sanitizer builds fly it), and but
# the command-line suites that exercise the program's options more than
# trixie's libraries (gl_limits_cli 29 s, outputs 12, kiosk 10, cli 9,
# hal_cli 7, results 3, wall_quick: the options' parsing and refusals,
# the same code under any compiler; the host's two builds run them)
D13_LEFT_OUT='autopilot|gl_limits_cli|outputs|kiosk|cli|hal_cli|results|wall_quick'
tests=$(d13_in "$D13_ROOT" sh -c "cd $B && meson test --no-rebuild --list --no-suite vm --no-suite display --no-suite soak \
	--no-suite gallery --no-suite pictures --no-suite structure" 2>/dev/null |
	sed 's|.* / ||' | grep -vxE "$D13_LEFT_OUT" | tr '\n' ' ')
d13_in "$D13_ROOT" sh -c "cd $B && EGL_LOG_LEVEL=fatal meson test --no-rebuild --print-errorlogs --num-processes 2 \
	$tests" >"$D13_LOGS/native-test.log" 2>&1
rc=$?
cp "$D13_ROOT$B/meson-logs/testlog.txt" "$D13_LOGS/native-testlog.txt" 2>/dev/null
grep -E "^ *[0-9]+/[0-9]+ " "$D13_LOGS/native-test.log"
# the individual checks the test programs report, as tools/test-all.sh counts them
p=$(grep -hoE '[0-9]+ passed, [0-9]+ failed' "$D13_LOGS/native-testlog.txt" | awk '{s+=$1} END {print s+0}')
f=$(grep -hoE '[0-9]+ passed, [0-9]+ failed' "$D13_LOGS/native-testlog.txt" | awk '{s+=$3} END {print s+0}')
d13_pass=$((d13_pass + p))
d13_fail=$((d13_fail + f))
if [ $rc -eq 0 ]; then
	d13_ok "meson test, suites but vm, display, soak, gallery, pictures, structure ($(($(date +%s) - t1)) s)"
else
	sed -n '/Summary of Failures/,$p' "$D13_LOGS/native-test.log"
	d13_bad "meson test (log: $D13_LOGS/native-testlog.txt)"
fi

# the installed layout (meson install into a scratch folder)
if d13_in "$D13_ROOT" sh -c "rm -rf /tmp/inst && meson install -C $B --no-rebuild --quiet --destdir /tmp/inst \
	>/dev/null" 2>"$D13_LOGS/native-install.log"; then
	i=$D13_ROOT/tmp/inst/usr/local
	miss=""
	for f in bin/isoterra share/man/man1/isoterra.1 lib/systemd/system/isoterra-kiosk.service etc/isoterra/kiosk.conf; do
		[ -f "$i/$f" ] || miss="$miss $f"
	done
	[ -z "$miss" ] && d13_ok "meson install (prefix /usr/local)" || d13_bad "meson install lacks$miss"
	# the unit names this prefix's binary and settings
	grep -q "^ExecStart=/usr/local/bin/isoterra " "$i/lib/systemd/system/isoterra-kiosk.service" &&
		grep -q -- "--config /usr/local/etc/isoterra/kiosk.conf" "$i/lib/systemd/system/isoterra-kiosk.service" &&
		d13_ok "kiosk unit paths" || d13_bad "kiosk unit paths: $(grep -A1 ExecStart "$i/lib/systemd/system/isoterra-kiosk.service")"
else
	cat "$D13_LOGS/native-install.log"
	d13_bad "meson install"
fi

# the gpio-sim VM test with this build (see the top): from the host, with
# the chroot's mounts gone (the guest mounts its own /proc, /sys, /dev, /run
# over the root's); caches (gpio-sim, initramfs, the guest's Mesa 25 shader
# cache) and the results folder in $D13/vm
if [ "$HAL_GPIOD2" = 1 ]; then
	d13_cleanup
	t1=$(date +%s)
	mkdir -p "$D13/vm"
	ISOTERRA_GUEST_ROOT=$D13_ROOT ISOTERRA_EXPECT_LIBGPIOD=libgpiod.so.3 ISOTERRA_VM_CACHE=$D13/vm/mesa-cache \
		sh "$D13_SRC/tests/vm/gpio_knobs.sh" $B/isoterra $B/tests/hal_probe "$D13/vm" >"$D13_LOGS/gpio-vm.log" 2>&1
	rc=$?
	line=$(grep -E '^gpio_knobs: [0-9]+ passed, [0-9]+ failed' "$D13_LOGS/gpio-vm.log" | tail -1)
	d13_pass=$((d13_pass + $(echo "$line" | awk '{print $2+0}')))
	d13_fail=$((d13_fail + $(echo "$line" | awk '{print $4+0}')))
	if [ $rc -eq 0 ]; then
		grep -E '^(VM|guest):' "$D13_LOGS/gpio-vm.log" | while read -r l; do d13_log "$l"; done
		d13_ok "gpio-sim VM test with libgpiod 2: $line ($(($(date +%s) - t1)) s)"
	elif [ $rc -eq 77 ]; then
		d13_log "gpio-sim VM test skipped: $(tail -1 "$D13_LOGS/gpio-vm.log")"
	else
		tail -40 "$D13_LOGS/gpio-vm.log"
		d13_bad "gpio-sim VM test with libgpiod 2 (log: $D13_LOGS/gpio-vm.log)"
	fi
fi

d13_log "Debian 13 suite: $(($(date +%s) - t0)) s"
d13_summary native
[ $d13_fail -eq 0 ]
