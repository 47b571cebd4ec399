#!/bin/sh
# isoterra — arm64: the Debian packages cross-built for arm64
# (`dpkg-buildpackage -a arm64`), checked, and the packaged arm64 binary run
# under qemu-user with arm64 Mesa's llvmpipe: the no-flag frame at 160x120,
# grid 32, compared with the x86-64 render of the same frame.  As root:
#
#   sh tools/arm64.sh            the suite
#   sh tools/arm64.sh prepare    only make the chroots ready and install every
#                                package the suite needs; runs nothing else.
#                                Ends with "== arm64 prepare: ok" (exit 0) or
#                                "== arm64 prepare: failed" (exit 1).  CI runs
#                                it early, in the background, so that the
#                                suite later finds everything installed.
#
# Where: Debian 13 chroots (tools/chroot.sh), not the Debian 12 host.
#  * Multiarch needs every Multi-Arch: same package (libc6, libegl1, Mesa,
#    libdrm...) at the same version for amd64 and arm64.  On the host the
#    amd64 side is whatever the CI image and tools/deps.sh installed; any
#    skew (a point release or binNMU the image predates) makes apt refuse, or
#    upgrade the host's own GL stack under the other suites' feet.  A chroot
#    installs both sides from the archive in one go, and a failure there
#    cannot break the host.
#  * The cross build has a chroot of its own, build-d13/arm64-root: the base
#    tarball plus arm64 as a foreign architecture, debian/control's
#    Build-Depends for arm64 (`apt-get build-dep -a arm64`, profiles cross and
#    nocheck), crossbuild-essential-arm64 (build-dep installs only the native
#    build-essential), qemu-user and arm64 Mesa's EGL for the smoke run.
#    libgdal-dev:arm64 cross-installs in trixie with the amd64 build tools
#    (GDAL's whole tree: about 460 packages, 310 MB of .debs, most of the
#    cold time), so isoterra-geotiff is cross-built too, no build profile
#    leaves it out.  Not in the Debian 13 suite's chroot (build-d13/root):
#    - the build dependencies resolve from the base system alone, as in
#      tools/debpkg.sh's build chroot (made again from the base tarball when
#      debian/control changes), so one that a cross build needs and
#      debian/control lacks fails here instead of being met by the native
#      suite's gcc, meson and -dev packages;
#    - `prepare` may run while tools/debian13.sh or tools/debpkg.sh run in
#      build-d13/root: its own chroot, its own lock (build-d13/.lock-arm64)
#      and its own download cache (build-d13/apt-archives-arm64, seeded with
#      hard links from build-d13/apt-archives: apt locks its cache folder,
#      and two apt runs sharing one would fail each other);
#    - the native suite's chroot does not carry GDAL's 460 arm64 packages.
#  * The x86-64 reference frame comes from the Debian 13 suite's build in
#    build-d13/root (build/native; built here, incrementally, when missing):
#    same Mesa 25, same LLVM, no second toolchain to download.
#  * The packaged binary runs from the .deb unpacked with dpkg -x (installing
#    the .deb would also pull in systemd's sysusers for the postinst, which
#    tools/debpkg.sh checks on amd64); `apt-get install -s` shows that the
#    .debs' dependencies resolve in trixie's arm64 archive, and arm64 ld.so
#    under qemu (`--list`) that every library they link is found.
#  * qemu-user is called explicitly (binfmt_misc needs the host kernel's
#    cooperation, which CI machines and containers do not always give); in
#    the chroot, /lib/ld-linux-aarch64.so.1 and /usr/lib/aarch64-linux-gnu
#    are where the arm64 binary looks, so no -L prefix is needed.
# Ends with "== debian13 arm64: N passed, M failed".  The arm64 .debs and the
# frames are left in build-d13/logs/.
# d13_ok and d13_bad return 0: `check && d13_ok ... || d13_bad ...` is an
# if-else here
# shellcheck disable=SC2015
set -u
# shellcheck source=tools/chroot.sh
. "$(dirname "$0")/chroot.sh"

X_ROOT=$D13/arm64-root
X_ARCHIVES=$D13/apt-archives-arm64
VERSION=$(sed -n '1s/^isoterra (\([^)]*\)).*/\1/p' "$D13_SRC/debian/changelog")
PKG=/pkg/isoterra-$VERSION

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

# the reference build in build-d13/root (tools/debian13.sh installs these and
# more); the cross chroot's packages beyond debian/control's Build-Depends
NATIVE="gcc libc6-dev meson ninja-build pkgconf libegl-dev libgles-dev libpng-dev libexpat1-dev libegl-mesa0 libgbm-dev libdrm-dev
	libgpiod-dev libwayland-dev wayland-protocols libx11-dev libx11-xcb-dev libxcb1-dev libxcb-shm0-dev"
CROSS="crossbuild-essential-arm64 qemu-user libegl-mesa0:arm64"

MODE=${1:-suite}
case "$MODE" in
suite | prepare) ;;
*) echo "usage: sh $0 [prepare]" >&2; exit 2 ;;
esac
d13_need_root "$@"
[ -n "$VERSION" ] || { echo "$0: no version in debian/changelog" >&2; exit 2; }
t0=$(date +%s)
fail() {
	d13_bad "$1"
	if [ "$MODE" = prepare ]; then echo "== arm64 prepare: failed"; else d13_summary arm64; fi
	exit 1
}

# the cross chroot's lock (fd 8; chroot.sh's d13_lock, fd 9, guards
# build-d13/root, the base tarball and the shared download cache)
mkdir -p "$D13" "$D13_LOGS"
exec 8>"$D13/.lock-arm64"
flock -w 3600 8 || { echo "$0: $X_ROOT is locked by another run" >&2; exit 2; }
[ "$MODE" = suite ] && d13_lock # the suite also renders in build-d13/root

# ---- the cross chroot, ready ---------------------------------------------------
t1=$(date +%s)
if [ ! -s "$D13_BASE" ]; then # debootstrap: one run at a time (the suite holds the lock already)
	[ "$MODE" = prepare ] && d13_lock
	d13_base || fail "Debian 13 base tarball"
	[ "$MODE" = prepare ] && exec 9>&- # lets tools/debian13.sh go on
fi
stamp=$(md5sum <"$D13_SRC/debian/control" | cut -c1-32)
if [ "$(cat "$X_ROOT/.isoterra-control" 2>/dev/null)" != "$stamp" ] || [ -n "$(find "$D13_BASE" -newer "$X_ROOT/.isoterra-control")" ] ||
	! d13_in "$X_ROOT" /bin/true 2>/dev/null || [ -n "$(d13_in "$X_ROOT" dpkg --audit 2>&1)" ]; then
	d13_log "cross build chroot: new one (debian/control changed, or none yet)"
	d13_fresh "$X_ROOT" || fail "cross build chroot"
fi
d13_mount "$X_ROOT" || fail "mounts"
# its own download cache over the shared one that d13_mount put there;
# unmounted first at exit (D13_MOUNTS: newest first)
mkdir -p "$X_ARCHIVES/partial"
cp -ln "$D13/apt-archives/"*.deb "$X_ARCHIVES/" 2>/dev/null
mount --bind "$X_ARCHIVES" "$X_ROOT/var/cache/apt/archives" && D13_MOUNTS="$X_ROOT/var/cache/apt/archives $D13_MOUNTS" ||
	fail "mount $X_ARCHIVES"
if ! d13_in "$X_ROOT" dpkg --print-foreign-architectures | grep -qx arm64; then
	d13_in "$X_ROOT" dpkg --add-architecture arm64 || fail "dpkg --add-architecture arm64"
	rm -f "$X_ROOT/.isoterra-updated" # the lists must gain arm64
fi
d13_copy_src "$X_ROOT" "$PKG" || fail "source copy"
if [ "$(cat "$X_ROOT/.isoterra-control" 2>/dev/null)" != "$stamp" ]; then
	d13_update "$X_ROOT" || fail "apt-get update"
	d13_log "apt-get build-dep -a arm64 -P cross,nocheck"
	d13_retry d13_in "$X_ROOT" apt-get build-dep -y -q -a arm64 -P cross,nocheck "$PKG" >"$D13_LOGS/arm64-build-dep.log" 2>&1 ||
		{ tail -30 "$D13_LOGS/arm64-build-dep.log"; fail "apt-get build-dep -a arm64"; }
	echo "$stamp" >"$X_ROOT/.isoterra-control"
fi
# shellcheck disable=SC2086 # a word list
d13_install "$X_ROOT" $CROSS || fail "packages"
# shellcheck disable=SC2016 # dpkg-query's format
d13_log "cross build chroot ready ($(($(date +%s) - t1)) s): $(d13_in "$X_ROOT" dpkg-query -W -f '${Package}:${Architecture} ${Version}, ' \
	gcc-aarch64-linux-gnu libgdal-dev:arm64 libgpiod-dev:arm64 libegl-mesa0:arm64 qemu-user 2>/dev/null)"
QEMU=$(d13_in "$X_ROOT" sh -c 'command -v qemu-aarch64-static || command -v qemu-aarch64') || fail "no qemu-aarch64 in the chroot"

# ---- build-d13/root, for the x86-64 reference -----------------------------------
[ "$MODE" = prepare ] && d13_lock # waits while tools/debian13.sh or debpkg.sh run there
d13_root || fail "Debian 13 chroot"
d13_mount "$D13_ROOT" || fail "mounts"
# shellcheck disable=SC2086 # a word list
d13_install "$D13_ROOT" $NATIVE || fail "packages"
if [ "$MODE" = prepare ]; then
	d13_log "arm64 prepare: $(($(date +%s) - t0)) s"
	echo "== arm64 prepare: ok"
	exit 0
fi
d13_copy_src "$D13_ROOT" || fail "source copy"

# ---- the cross build of the packages ---------------------------------------------
rm -f "$X_ROOT/pkg/"*.deb "$X_ROOT/pkg/"*.ddeb "$X_ROOT/pkg/"*.changes "$X_ROOT/pkg/"*.buildinfo
t1=$(date +%s)
opts="nocheck parallel=$(nproc)"
if d13_in "$X_ROOT" sh -c "cd $PKG && DEB_BUILD_OPTIONS='$opts' DEB_BUILD_PROFILES='cross nocheck' \
	dpkg-buildpackage -a arm64 -b -us -uc" >"$D13_LOGS/arm64-pkg-build.log" 2>&1; then
	d13_ok "dpkg-buildpackage -a arm64 -b ($opts, profiles cross nocheck, $(($(date +%s) - t1)) s)"
else
	grep -E "error|Error" "$D13_LOGS/arm64-pkg-build.log" | tail -20
	tail -20 "$D13_LOGS/arm64-pkg-build.log"
	fail "dpkg-buildpackage -a arm64 (log: $D13_LOGS/arm64-pkg-build.log)"
fi
deb=/pkg/isoterra_${VERSION}_arm64.deb
gdeb=/pkg/isoterra-geotiff_${VERSION}_arm64.deb
for f in $deb $gdeb; do
	[ -s "$X_ROOT$f" ] || fail "no ${f#/pkg/}"
	a=$(d13_in "$X_ROOT" dpkg-deb -f "$f" Architecture)
	[ "$a" = arm64 ] && d13_ok "${f#/pkg/}: Architecture $a" || d13_bad "${f#/pkg/}: Architecture '$a', not arm64"
	cp "$X_ROOT$f" "$D13_LOGS/"
done
# the configuration the package was built with (debian/rules requires the
# backends and the GPIO knobs; checked here all the same)
mlog=$X_ROOT$PKG/obj-aarch64-linux-gnu/meson-logs/meson-log.txt
grep -qE "platform backends *: device surfaceless gbm wayland x11" "$D13_LOGS/arm64-pkg-build.log" "$mlog" 2>/dev/null &&
	d13_ok "arm64 build has the gbm, wayland and x11 backends" || d13_bad "arm64 build lacks display backends"
gpiod=$(grep -o "GPIO knobs: libgpiod [^ ]*, API v[0-9]" "$mlog" 2>/dev/null | tail -1)
case "$gpiod" in
*"API v2") d13_ok "arm64 build has the GPIO knobs: ${gpiod#GPIO knobs: }" ;;
*) d13_bad "arm64 build: the GPIO knobs are not on libgpiod 2: '${gpiod:-built out}'" ;;
esac
dep=$(d13_in "$X_ROOT" dpkg-deb -f "$deb" Depends)
case "$dep" in
*libgpiod*) d13_ok "isoterra (arm64) depends on $(echo "$dep" | grep -o 'libgpiod[^,]*') (GPIO knobs)" ;;
*) d13_bad "isoterra (arm64) does not depend on libgpiod: $dep" ;;
esac
mod=usr/lib/aarch64-linux-gnu/isoterra/isoterra-geotiff.so
gdep=$(d13_in "$X_ROOT" dpkg-deb -f "$gdeb" Depends)
d13_in "$X_ROOT" dpkg-deb -c "$gdeb" | grep -q " \./$mod\$" && echo "$gdep" | grep -q libgdal &&
	d13_ok "isoterra-geotiff (arm64) carries /$mod, depends on $(echo "$gdep" | grep -o 'libgdal[^,]*')" ||
	d13_bad "isoterra-geotiff (arm64): /$mod or libgdal missing: $(d13_in "$X_ROOT" dpkg-deb -c "$gdeb" | grep -o '\./usr/lib/.*\.so'); $gdep"
# the .debs' dependencies resolve in trixie's arm64 archive (simulated)
if d13_in "$X_ROOT" apt-get install -s -q "$deb" "$gdeb" >"$D13_LOGS/arm64-pkg-install-s.log" 2>&1 &&
	grep -q "^Inst isoterra:arm64" "$D13_LOGS/arm64-pkg-install-s.log" && grep -q "^Inst isoterra-geotiff:arm64" "$D13_LOGS/arm64-pkg-install-s.log"; then
	d13_ok "apt-get install -s of both arm64 .debs: $(grep -c '^Inst ' "$D13_LOGS/arm64-pkg-install-s.log") packages"
else
	tail -15 "$D13_LOGS/arm64-pkg-install-s.log"
	d13_bad "the arm64 .debs' dependencies do not resolve (log: $D13_LOGS/arm64-pkg-install-s.log)"
fi

# ---- the packaged binary -----------------------------------------------------------
x=/tmp/arm64-pkg
rm -rf "${X_ROOT:?}$x"
d13_in "$X_ROOT" dpkg -x "$deb" "$x" && d13_in "$X_ROOT" dpkg -x "$gdeb" "$x" || fail "dpkg -x the arm64 .debs"
# AArch64 executables (ELF e_machine 0xb7 at offset 18)
for f in usr/bin/isoterra $mod; do
	m=$(od -An -tx1 -j18 -N2 "$X_ROOT$x/$f" | tr -d ' ')
	[ "$m" = b700 ] && d13_ok "/$f is an AArch64 ELF" || d13_bad "/$f's e_machine is '$m', not AArch64 (b700)"
done
# every library they link, found by arm64 ld.so
for f in usr/bin/isoterra $mod; do
	log=$D13_LOGS/arm64-ldd-${f##*/}.log
	if d13_in "$X_ROOT" "$QEMU" /lib/ld-linux-aarch64.so.1 --list "$x/$f" >"$log" 2>&1 && ! grep -q "not found" "$log"; then
		d13_ok "/$f: $(grep -c '=>' "$log") libraries found by arm64 ld.so: $(awk '$1 ~ /^lib(gpiod|gdal)/ { print $1 " => " $3 }' "$log")"
	else
		d13_bad "/$f: $(grep -E 'not found|rror' "$log" | tr '\n' ' ')"
	fi
done

# ---- the smoke run -------------------------------------------------------------
out=/tmp/arm64-smoke
rm -rf "${X_ROOT:?}$out" "${D13_ROOT:?}$out"
mkdir -p "$X_ROOT$out" "$D13_ROOT$out"
t1=$(date +%s)
if d13_in "$X_ROOT" sh -c "cd $out && EGL_LOG_LEVEL=fatal timeout 900 $QEMU $x/usr/bin/isoterra --version &&
	EGL_LOG_LEVEL=fatal timeout 900 $QEMU $x/usr/bin/isoterra --size $SIZE --grid $GRID --out arm64.png --verbose" \
	>"$D13_LOGS/arm64-smoke.log" 2>&1 && [ -s "$X_ROOT$out/arm64.png" ]; then
	d13_ok "packaged arm64 isoterra renders under $(basename "$QEMU") ($(($(date +%s) - t1)) s): $(grep -o "GL_RENDERER '[^']*'" "$D13_LOGS/arm64-smoke.log" | head -1)"
else
	tail -20 "$D13_LOGS/arm64-smoke.log"
	fail "arm64 render under qemu"
fi
grep -q "GL_RENDERER 'llvmpipe" "$D13_LOGS/arm64-smoke.log" && d13_ok "arm64 Mesa's llvmpipe" ||
	d13_bad "not llvmpipe: $(grep GL_RENDERER "$D13_LOGS/arm64-smoke.log")"
# the GeoTIFF module, from the package: it loads (GDAL's arm64 libraries
# and all) and GDAL itself rejects a file that is no TIFF
printf 'II*\000 this is not a TIFF' >"$X_ROOT$out/bad.tif"
d13_in "$X_ROOT" sh -c "cd $out && ISOTERRA_MODULE_DIR=$x/${mod%/*} EGL_LOG_LEVEL=fatal timeout 900 $QEMU $x/usr/bin/isoterra \
	--size 64x48 --grid 16 --out g.png --field heightmap --heightmap bad.tif" >"$D13_LOGS/arm64-geotiff.log" 2>&1
rc=$?
grep -q "bad.tif.*GDAL cannot read it as a GeoTIFF" "$D13_LOGS/arm64-geotiff.log" && [ $rc -ne 0 ] &&
	d13_ok "the packaged GeoTIFF module loads under qemu, GDAL rejects a bad TIFF: $(grep -o 'GDAL cannot.*' "$D13_LOGS/arm64-geotiff.log" | head -1)" ||
	d13_bad "GeoTIFF module under qemu (rc $rc): $(tail -3 "$D13_LOGS/arm64-geotiff.log")"

# ---- the x86-64 reference: the Debian 13 suite's build -------------------------------
t1=$(date +%s)
B=/build/native
setup="setup $B /src"
[ -f "$D13_ROOT$B/build.ninja" ] && setup="configure $B"
# shellcheck disable=SC2086 # a word list
d13_in "$D13_ROOT" meson $setup -Dwerror=true -Dbuildtype=debugoptimized -Dc_args= >"$D13_LOGS/native-setup.log" 2>&1 ||
	{ tail -30 "$D13_LOGS/native-setup.log"; fail "meson setup (native)"; }
d13_in "$D13_ROOT" ninja -C "$B" >"$D13_LOGS/native-build.log" 2>&1 || { tail -40 "$D13_LOGS/native-build.log"; fail "build (native)"; }
d13_ok "native build ($(($(date +%s) - t1)) s)"
cp "$X_ROOT$out/arm64.png" "$D13_ROOT$out/"
d13_in "$D13_ROOT" sh -c "cd $out && EGL_LOG_LEVEL=fatal $B/isoterra --size $SIZE --grid $GRID --out x86_64.png" \
	>"$D13_LOGS/native-smoke.log" 2>&1 || { cat "$D13_LOGS/native-smoke.log"; fail "x86-64 render"; }
if d13_in "$D13_ROOT" $B/tests/imgcmp "$out/arm64.png" "$out/x86_64.png" --threshold $THRESHOLD \
	--max-mean $MAX_MEAN --max-frac $MAX_FRAC --diff "$out/diff.png" >"$D13_LOGS/arm64-imgcmp.log" 2>&1; then
	d13_ok "arm64 frame = x86-64 frame within mean $MAX_MEAN, $MAX_FRAC over $THRESHOLD: $(cat "$D13_LOGS/arm64-imgcmp.log")"
else
	d13_bad "arm64 frame differs from x86-64: $(cat "$D13_LOGS/arm64-imgcmp.log")"
fi
cp "$D13_ROOT$out/"*.png "$D13_LOGS/" 2>/dev/null

d13_log "arm64 suite: $(($(date +%s) - t0)) s"
d13_summary arm64
[ "$d13_fail" -eq 0 ]
