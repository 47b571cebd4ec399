#!/bin/sh
# isoterra — arm64: a cross build with Debian's crossbuild-essential-arm64
# and the :arm64 development packages (tools/cross/arm64-linux-gnu.ini), and
# a smoke run of the arm64 binary under qemu-user with arm64 Mesa's
# llvmpipe: the no-flag frame at 160x120, grid 32, compared with the x86-64
# render of the same frame.  As root: sh tools/arm64.sh
#
# Where: in the Debian 13 chroot of tools/debian13.sh (build-d13/root), with
# arm64 added as a foreign architecture, not on the Debian 12 host.
#  * Multiarch needs every Multi-Arch: same package (libc6, libegl1, Mesa,
#    libdrm...) at the same version for amd64 and arm64.  On the host the
#    amd64 side is whatever the CI image and tools/deps.sh installed; any
#    skew (a point release or binNMU the image predates) makes apt refuse, or
#    upgrade the host's own GL stack under the other suites' feet.  The
#    chroot installs both sides from the archive in one go, and a failure
#    there cannot break the host.
#  * It is the same chroot as the Debian 13 suite: the x86-64 reference
#    frame comes from its build (same Mesa 25, same LLVM, no second
#    toolchain to download), and the packages stay cached.
#  * qemu-user is called explicitly (binfmt_misc needs the host kernel's
#    cooperation, which CI machines and containers do not always give); in
#    the chroot, /lib/ld-linux-aarch64.so.1 and /usr/lib/aarch64-linux-gnu
#    are where the arm64 binary looks, so no -L prefix is needed.
# Ends with "== debian13 arm64: N passed, M failed".
set -u
. "$(dirname "$0")/chroot.sh"

# the arm64 frame may differ from the x86-64 one where the two llvmpipe
# back ends round differently (fused multiply-add on AArch64): a few
# pixels along silhouettes and the iso-surface's knife edges.  imgcmp's
# tolerance: mean |difference| <= MAX_MEAN (0..255 per channel), at most
# MAX_FRAC of the pixels over THRESHOLD.
# Measured on Debian 13 (Mesa 25.0.7, LLVM 19): the diorama frame mean
# 0.13, largest 4; the open landscape (water waves over much of the frame,
# whose normals come from noise: small differences everywhere on the water)
# mean 0.68, largest 7; none over 16 in either.
THRESHOLD=16
MAX_MEAN=1.0
MAX_FRAC=0.002
SIZE=160x120
GRID=32

# libgpiod-dev on both sides: the GPIO knobs on the hal's libgpiod-2 backend
# (Raspberry Pi OS and Debian 13 ship libgpiod 2), checked in the arm64 build
NATIVE="gcc libc6-dev meson ninja-build pkgconf libegl-dev libgles-dev libpng-dev libegl-mesa0 libgbm-dev libdrm-dev
	libgpiod-dev libwayland-dev wayland-protocols libx11-dev libx11-xcb-dev libxcb1-dev"
ARM64="crossbuild-essential-arm64 libc6-dev:arm64 libegl-dev:arm64 libgles-dev:arm64 libpng-dev:arm64
	libgbm-dev:arm64 libdrm-dev:arm64 libgpiod-dev:arm64 libwayland-dev:arm64 libx11-dev:arm64 libx11-xcb-dev:arm64
	libxcb1-dev:arm64 libegl-mesa0:arm64 qemu-user"

d13_need_root "$@"
d13_lock
t0=$(date +%s)
fail() { d13_bad "$1"; d13_summary arm64; exit 1; }

d13_root || fail "Debian 13 chroot"
d13_mount "$D13_ROOT" || fail "mounts"
if ! d13_in "$D13_ROOT" dpkg --print-foreign-architectures | grep -qx arm64; then
	d13_in "$D13_ROOT" dpkg --add-architecture arm64 || fail "dpkg --add-architecture arm64"
	rm -f "$D13_ROOT/.isoterra-updated" # the lists must gain arm64
fi
# shellcheck disable=SC2086 # word lists
d13_install "$D13_ROOT" $NATIVE $ARM64 || fail "packages"
d13_log "chroot ready ($(($(date +%s) - t0)) s): $(d13_in "$D13_ROOT" dpkg-query -W -f '${Package}:${Architecture} ${Version}, ' \
	gcc-aarch64-linux-gnu libegl-mesa0:arm64 qemu-user 2>/dev/null)"
d13_copy_src "$D13_ROOT" || fail "source copy"

QEMU=$(d13_in "$D13_ROOT" sh -c 'command -v qemu-aarch64-static || command -v qemu-aarch64') || fail "no qemu-aarch64 in the chroot"

# ---- the two builds: arm64 (cross) and x86-64 (the reference) -------------
build() { # NAME DIR setup-args...
	name=$1
	dir=$2
	shift 2
	setup="setup $dir /src"
	[ -f "$D13_ROOT$dir/build.ninja" ] && setup="configure $dir"
	t1=$(date +%s)
	# shellcheck disable=SC2086
	d13_in "$D13_ROOT" meson $setup "$@" -Dwerror=true -Dbuildtype=debugoptimized -Dc_args= \
		>"$D13_LOGS/$name-setup.log" 2>&1 || { tail -30 "$D13_LOGS/$name-setup.log"; fail "meson setup ($name)"; }
	d13_in "$D13_ROOT" ninja -C "$dir" >"$D13_LOGS/$name-build.log" 2>&1 ||
		{ tail -40 "$D13_LOGS/$name-build.log"; fail "build ($name)"; }
	d13_ok "$name build ($(($(date +%s) - t1)) s)"
}
cross_args="--cross-file /src/tools/cross/arm64-linux-gnu.ini"
# the cross file is given at setup only (meson keeps it)
[ -f "$D13_ROOT/build/arm64/build.ninja" ] && cross_args=""
# shellcheck disable=SC2086
build arm64 /build/arm64 $cross_args
build native /build/native

# an AArch64 executable (ELF e_machine 0xb7 at offset 18)
m=$(od -An -tx1 -j18 -N2 "$D13_ROOT/build/arm64/isoterra" | tr -d ' ')
[ "$m" = b700 ] && d13_ok "isoterra is an AArch64 ELF" || d13_bad "isoterra's e_machine is $m, not AArch64 (b700)"
grep -q "platform backends: device surfaceless gbm wayland x11" "$D13_LOGS/arm64-setup.log" ||
	grep -q "platform backends: device surfaceless gbm wayland x11" "$D13_ROOT/build/arm64/meson-logs/meson-log.txt" &&
	d13_ok "arm64 build has the gbm, wayland and x11 backends" || d13_bad "arm64 build lacks display backends"
gpiod=$(grep -o "GPIO knobs: libgpiod [^ ]*, API v[0-9]" "$D13_ROOT/build/arm64/meson-logs/meson-log.txt" | tail -1)
case "$gpiod" in
*"API v2") d13_ok "arm64 build has the GPIO knobs: ${gpiod#GPIO knobs: }" ;;
*) d13_bad "arm64 build: the GPIO knobs are not on libgpiod 2: '${gpiod:-built out}'" ;;
esac

# ---- the smoke run -----------------------------------------------------------
out=/tmp/arm64-smoke
rm -rf "${D13_ROOT:?}$out"
mkdir -p "$D13_ROOT$out"
t1=$(date +%s)
if d13_in "$D13_ROOT" sh -c "cd $out && EGL_LOG_LEVEL=fatal timeout 900 $QEMU /build/arm64/isoterra --version &&
	EGL_LOG_LEVEL=fatal timeout 900 $QEMU /build/arm64/isoterra --size $SIZE --grid $GRID --out arm64.png --verbose" \
	>"$D13_LOGS/arm64-smoke.log" 2>&1 && [ -s "$D13_ROOT$out/arm64.png" ]; then
	d13_ok "arm64 render under $(basename "$QEMU") ($(($(date +%s) - t1)) s): $(grep -o "GL_RENDERER '[^']*'" "$D13_LOGS/arm64-smoke.log" | head -1)"
else
	tail -20 "$D13_LOGS/arm64-smoke.log"
	fail "arm64 render under qemu"
fi
grep -q "GL_RENDERER 'llvmpipe" "$D13_LOGS/arm64-smoke.log" && d13_ok "arm64 Mesa's llvmpipe" ||
	d13_bad "not llvmpipe: $(grep GL_RENDERER "$D13_LOGS/arm64-smoke.log")"
d13_in "$D13_ROOT" sh -c "cd $out && EGL_LOG_LEVEL=fatal /build/native/isoterra --size $SIZE --grid $GRID --out x86_64.png" \
	>"$D13_LOGS/native-smoke.log" 2>&1 || { cat "$D13_LOGS/native-smoke.log"; fail "x86-64 render"; }
if d13_in "$D13_ROOT" /build/native/tests/imgcmp "$out/arm64.png" "$out/x86_64.png" --threshold $THRESHOLD \
	--max-mean $MAX_MEAN --max-frac $MAX_FRAC --diff "$out/diff.png" >"$D13_LOGS/arm64-imgcmp.log" 2>&1; then
	d13_ok "arm64 frame = x86-64 frame within mean $MAX_MEAN, $MAX_FRAC over $THRESHOLD: $(cat "$D13_LOGS/arm64-imgcmp.log")"
else
	d13_bad "arm64 frame differs from x86-64: $(cat "$D13_LOGS/arm64-imgcmp.log")"
fi
cp "$D13_ROOT$out/"*.png "$D13_LOGS/" 2>/dev/null

d13_log "arm64 suite: $(($(date +%s) - t0)) s"
d13_summary arm64
[ $d13_fail -eq 0 ]
