#!/bin/sh
# isoterra — the Debian packages, built and installed on Debian 13 and 12.  As root:
#
#   sh tools/debpkg.sh
#   sh tools/debpkg.sh prepare   only the chroots and base tarballs of parts
#                                1-4, their packages installed (tools/test-all.sh
#                                runs this in the background early on)
#
# 1. Build: `dpkg-buildpackage -b -us -uc` in a chroot that has only the
#    base system and debian/control's Build-Depends (apt-get build-dep), so
#    a missing build dependency fails here.  That chroot (build-d13/pkg-root)
#    is cached and made again from the base tarball when debian/control
#    changes.  The package's own tests run (debian/rules: every suite but
#    vm and display); ISOTERRA_DEB_NOCHECK=1 skips them (tools/test-all.sh
#    does: its Debian 13 suite ran them on these sources, on trixie).
# 2. lintian, in the build chroot of tools/debian13.sh: errors and warnings
#    fail (overrides, each with its reason, live in debian/).
# 3. Install: a fresh minbase chroot, `apt-get install ./isoterra_*.deb`
#    (dependencies from the archive, no recommends), then the installed
#    binary renders a frame that must equal the one the source build
#    renders, the example /etc/isoterra/kiosk.conf parses, the man page,
#    unit (not enabled), conffile and documentation are in place; the
#    package links libgpiod (the GPIO knobs), isoterra-geotiff carries the
#    GDAL module, sysusers made the user "isoterra" (groups video, render,
#    input), and `systemd-analyze security --offline=yes` rates the
#    installed unit <= 2.5 (--threshold=25).
# 3b. The installed unit runs for real (tests/vm/kiosk_unit.sh): QEMU boots
#    systemd as PID 1 from an install chroot, the enabled unit drives the
#    virtio-gpu display: on the Debian 12 install of part 4 (ISOTERRA_DEB_VM=13:
#    on this one; 0: left out).
# 4. Debian 12: built on the host (Debian 12, tools/deps.sh's packages;
#    libgpiod 1.6), installed into a fresh bookworm chroot, the same checks
#    (ISOTERRA_DEB12=0: left out).
# Ends with "== debian13 package: N passed, M failed".  The .deb, .changes
# and lintian's report are left in build-d13/logs/.
set -u
. "$(dirname "$0")/chroot.sh"

PKG_ROOT=$D13/pkg-root
INST_ROOT=$D13/install-root
VERSION=$(sed -n '1s/^isoterra (\([^)]*\)).*/\1/p' "$D13_SRC/debian/changelog")

# pkg_checks ROOT LIBGPIOD: what the installed packages must give, in ROOT
pkg_checks() {
	r=$1
	# the GPIO knobs: the program links the distribution's libgpiod
	d13_in "$r" ldd /usr/bin/isoterra | grep -q "$2 " && d13_ok "isoterra links $2 (GPIO knobs)" ||
		d13_bad "isoterra does not link $2: $(d13_in "$r" dpkg-query -W -f '${Depends}' isoterra)"
	# GeoTIFF: the module, in its own package, its libraries all found
	mod=$(d13_in "$r" dpkg -L isoterra-geotiff | grep '/isoterra/isoterra-geotiff\.so$')
	if [ -n "$mod" ] && d13_in "$r" ldd "$mod" >"$D13_LOGS/pkg-ldd.log" 2>&1 && ! grep -q "not found" "$D13_LOGS/pkg-ldd.log" &&
		grep -q libgdal "$D13_LOGS/pkg-ldd.log"; then
		d13_ok "isoterra-geotiff: $mod, $(grep -o 'libgdal[^ ]*' "$D13_LOGS/pkg-ldd.log" | head -1) resolved"
	else
		d13_bad "isoterra-geotiff's module '$mod': $(grep -E 'not found|gdal' "$D13_LOGS/pkg-ldd.log")"
	fi
	d13_in "$r" ldd /usr/bin/isoterra | grep -q libgdal && d13_bad "isoterra itself links GDAL" ||
		d13_ok "isoterra itself does not link GDAL"
	# and it works: the installed program reads a GeoTIFF through the
	# installed module and this distribution's GDAL (the package build runs
	# no tests in CI, ISOTERRA_DEB_NOCHECK)
	python3 "$D13_SRC/tests/mk_tiff.py" "$r/tmp/hill.tif" && rm -f "$r/tmp/hill.png"
	if d13_in "$r" sh -c "cd /tmp && EGL_LOG_LEVEL=fatal isoterra --field heightmap --heightmap /tmp/hill.tif \
		--heightmap-scale 2 --size 64x48 --grid 16 --out /tmp/hill.png" >"$D13_LOGS/pkg-geotiff.log" 2>&1 &&
		[ -s "$r/tmp/hill.png" ]; then
		d13_ok "a GeoTIFF heightmap through the installed module: $(tail -1 "$D13_LOGS/pkg-geotiff.log")"
	else
		d13_bad "a GeoTIFF heightmap through the installed module: $(tail -2 "$D13_LOGS/pkg-geotiff.log")"
	fi
	# the system user, from sysusers.d
	pw=$(d13_in "$r" getent passwd isoterra)
	groups=$(d13_in "$r" id -nG isoterra 2>/dev/null)
	case "$pw" in
	isoterra:*:/var/lib/isoterra:*nologin) d13_ok "user isoterra: $pw" ;;
	*) d13_bad "user isoterra: '$pw'" ;;
	esac
	miss=""
	for g in video render input; do
		echo " $groups " | grep -q " $g " || miss="$miss $g"
	done
	[ -z "$miss" ] && d13_ok "isoterra's groups: $groups" || d13_bad "isoterra is not in$miss ($groups)"
	echo " $groups " | grep -q " gpio " && d13_bad "isoterra in gpio where no such group was" || true
	# a gpio group (a board image's): the postinst adds the user to it
	d13_in "$r" groupadd -r gpio && d13_in "$r" dpkg-reconfigure isoterra >/dev/null 2>&1
	d13_in "$r" id -nG isoterra | tr ' ' '\n' | grep -qx gpio && d13_ok "with a gpio group, the postinst adds isoterra to it" ||
		d13_bad "gpio group: isoterra not added ($(d13_in "$r" id -nG isoterra))"
	# the unit's sandbox: systemd-analyze's exposure rating at most 2.5
	unit=/usr/lib/systemd/system/isoterra-kiosk.service
	sa="d13_in $r systemd-analyze"
	d13_in "$r" sh -c 'command -v systemd-analyze' >/dev/null || sa="systemd-analyze" unit=$r$unit
	if $sa security --offline=yes --threshold=25 "$unit" >"$D13_LOGS/pkg-security.log" 2>&1; then
		d13_ok "systemd-analyze security --offline=yes --threshold=25: $(grep -o 'exposure level.*' "$D13_LOGS/pkg-security.log")"
	else
		grep -E '✗|exposure' "$D13_LOGS/pkg-security.log"
		d13_bad "the unit's exposure is over 2.5 (log: $D13_LOGS/pkg-security.log)"
	fi
}

d13_need_root "$@"
d13_lock
t0=$(date +%s)
fail() { d13_bad "$1"; d13_summary package; exit 1; }
[ -n "$VERSION" ] || fail "no version in debian/changelog"
d13_root || fail "Debian 13 chroot"

# ---- 1. build in a chroot with only the build dependencies -------------------
stamp=$(cat "$D13_SRC/debian/control" | md5sum | cut -c1-32)
if [ "$(cat "$PKG_ROOT/.isoterra-control" 2>/dev/null)" != "$stamp" ] || [ "$PKG_ROOT/.isoterra-control" -ot "$D13_BASE" ] ||
	! d13_in "$PKG_ROOT" /bin/true 2>/dev/null || [ -n "$(d13_in "$PKG_ROOT" dpkg --audit 2>&1)" ]; then
	d13_log "package build chroot: new one (debian/control changed, or none yet)"
	d13_fresh "$PKG_ROOT" || fail "package build chroot"
fi
d13_mount "$PKG_ROOT" || fail "mounts"
d13_copy_src "$PKG_ROOT" "/pkg/isoterra-$VERSION" || fail "source copy"
rm -f "$PKG_ROOT/pkg/"*.deb "$PKG_ROOT/pkg/"*.changes "$PKG_ROOT/pkg/"*.buildinfo
if [ "$(cat "$PKG_ROOT/.isoterra-control" 2>/dev/null)" != "$stamp" ]; then
	d13_update "$PKG_ROOT" || fail "apt-get update"
	d13_retry d13_in "$PKG_ROOT" apt-get build-dep -y -q "/pkg/isoterra-$VERSION" >"$D13_LOGS/pkg-build-dep.log" 2>&1 ||
		{ tail -30 "$D13_LOGS/pkg-build-dep.log"; fail "apt-get build-dep"; }
	echo "$stamp" >"$PKG_ROOT/.isoterra-control"
fi
if [ "${1:-}" = prepare ]; then
	d13_cleanup
	d13_mount "$D13_ROOT" && d13_install "$D13_ROOT" lintian || fail "lintian"
	d13_cleanup
	if [ "${ISOTERRA_DEB12:-1}" = 1 ]; then
		D13_SUITE=bookworm D13_BASE=$D13/bookworm-minbase.tar
		d13_base || fail "the bookworm base tarball"
	fi
	d13_log "package suite prepared ($(($(date +%s) - t0)) s)"
	echo "== debian13 package prepare: ok"
	exit 0
fi
t1=$(date +%s)
opts="parallel=$(nproc)"
[ "${ISOTERRA_DEB_NOCHECK:-0}" = 1 ] && opts="$opts nocheck"
if d13_in "$PKG_ROOT" sh -c "cd /pkg/isoterra-$VERSION && DEB_BUILD_OPTIONS='$opts' dpkg-buildpackage -b -us -uc" \
	>"$D13_LOGS/pkg-build.log" 2>&1; then
	d13_ok "dpkg-buildpackage -b ($opts, $(($(date +%s) - t1)) s)"
else
	grep -E "FAIL|error|Error" "$D13_LOGS/pkg-build.log" | tail -20
	tail -20 "$D13_LOGS/pkg-build.log"
	fail "dpkg-buildpackage (log: $D13_LOGS/pkg-build.log)"
fi
arch=$(d13_in "$PKG_ROOT" dpkg --print-architecture)
deb=isoterra_${VERSION}_$arch.deb
gdeb=isoterra-geotiff_${VERSION}_$arch.deb
[ -s "$PKG_ROOT/pkg/$deb" ] && d13_ok "$deb" || fail "no $deb"
[ -s "$PKG_ROOT/pkg/$gdeb" ] && d13_ok "$gdeb" || fail "no $gdeb"
cp "$PKG_ROOT/pkg/$deb" "$PKG_ROOT/pkg/$gdeb" "$PKG_ROOT/pkg/isoterra_${VERSION}_$arch.changes" "$D13_LOGS/"
d13_cleanup

# ---- 2. lintian ----------------------------------------------------------------
d13_mount "$D13_ROOT" || fail "mounts"
d13_install "$D13_ROOT" lintian || fail "lintian"
rm -rf "$D13_ROOT/tmp/lintian" && mkdir -p "$D13_ROOT/tmp/lintian"
cp "$PKG_ROOT/pkg/"*.deb "$PKG_ROOT/pkg/"*.changes "$PKG_ROOT/pkg/"*.buildinfo "$D13_ROOT/tmp/lintian/"
t1=$(date +%s)
d13_in "$D13_ROOT" lintian --fail-on error,warning --info --display-level ">=pedantic" \
	"/tmp/lintian/isoterra_${VERSION}_$arch.changes" >"$D13_LOGS/lintian.log" 2>&1
rc=$?
cat "$D13_LOGS/lintian.log"
tags=$(grep -cE '^[EWIPX]: ' "$D13_LOGS/lintian.log")
[ $rc -eq 0 ] && d13_ok "lintian: no errors or warnings ($tags info/pedantic tags, $(($(date +%s) - t1)) s)" ||
	d13_bad "lintian: errors or warnings (log: $D13_LOGS/lintian.log)"

# the reference frame, from the source build of tools/debian13.sh (when there)
ref=""
if [ -x "$D13_ROOT/build/native/isoterra" ] && [ -x "$D13_ROOT/build/native/tests/imgcmp" ]; then
	d13_in "$D13_ROOT" sh -c "EGL_LOG_LEVEL=fatal /build/native/isoterra --size 64x48 --grid 16 --out /tmp/ref.png" \
		>/dev/null 2>&1 && ref=$D13_ROOT/tmp/ref.png
fi

# ---- 3. install into a fresh chroot --------------------------------------------
t1=$(date +%s)
d13_fresh "$INST_ROOT" || fail "install chroot"
d13_mount "$INST_ROOT" || fail "mounts"
cp "$PKG_ROOT/pkg/$deb" "$PKG_ROOT/pkg/$gdeb" "$INST_ROOT/tmp/"
d13_update "$INST_ROOT" || fail "apt-get update"
if d13_retry d13_in "$INST_ROOT" apt-get install -y -q "/tmp/$deb" "/tmp/$gdeb" >"$D13_LOGS/pkg-install.log" 2>&1; then
	d13_ok "apt-get install ./$deb ./$gdeb: $(grep -cE '^(Unpacking|Preparing to unpack)' "$D13_LOGS/pkg-install.log") unpack steps ($(($(date +%s) - t1)) s)"
else
	tail -30 "$D13_LOGS/pkg-install.log"
	fail "apt-get install ./$deb ./$gdeb"
fi
[ "$(d13_in "$INST_ROOT" dpkg-query -W -f '${db:Status-Status}' isoterra)" = installed ] && d13_ok "isoterra installed" ||
	d13_bad "isoterra not installed"
pkg_checks "$INST_ROOT" libgpiod.so.3
if d13_in "$INST_ROOT" sh -c "cd /tmp && EGL_LOG_LEVEL=fatal isoterra --size 64x48 --grid 16 --out /tmp/x.png" \
	>"$D13_LOGS/pkg-render.log" 2>&1; then
	d13_ok "installed isoterra renders: $(tail -1 "$D13_LOGS/pkg-render.log")"
else
	cat "$D13_LOGS/pkg-render.log"
	d13_bad "installed isoterra does not render"
fi
png=$INST_ROOT/tmp/x.png
sig=$(od -An -tx1 -N8 "$png" 2>/dev/null | tr -d ' \n')
size=$(wc -c <"$png" 2>/dev/null || echo 0)
[ "$sig" = 89504e470d0a1a0a ] && [ "$size" -gt 2000 ] && d13_ok "x.png: a PNG of $size bytes" ||
	d13_bad "x.png: signature '$sig', $size bytes"
if [ -n "$ref" ]; then
	cp "$png" "$D13_ROOT/tmp/installed.png"
	d13_in "$D13_ROOT" /build/native/tests/imgcmp /tmp/installed.png /tmp/ref.png >"$D13_LOGS/pkg-imgcmp.log" 2>&1 &&
		d13_ok "the frame equals the source build's: $(cat "$D13_LOGS/pkg-imgcmp.log")" ||
		d13_bad "the frame differs from the source build's: $(cat "$D13_LOGS/pkg-imgcmp.log")"
else
	d13_log "no source build in $D13_ROOT (tools/debian13.sh): frame not compared"
fi
cp "$png" "$D13_LOGS/pkg-x.png" 2>/dev/null
# the example settings parse (and apply: a frame with them)
d13_in "$INST_ROOT" sh -c "EGL_LOG_LEVEL=fatal isoterra --config /etc/isoterra/kiosk.conf --size 64x48 --grid 16 \
	--out /tmp/y.png" >"$D13_LOGS/pkg-conf.log" 2>&1 && d13_ok "/etc/isoterra/kiosk.conf parses" ||
	d13_bad "/etc/isoterra/kiosk.conf: $(cat "$D13_LOGS/pkg-conf.log")"
d13_in "$INST_ROOT" dpkg-query -W -f '${Conffiles}\n' isoterra | grep -q "/etc/isoterra/kiosk.conf" &&
	d13_ok "kiosk.conf is a conffile" || d13_bad "kiosk.conf is not a conffile"
miss=""
for f in usr/bin/isoterra usr/share/man/man1/isoterra.1.gz usr/lib/systemd/system/isoterra-kiosk.service usr/lib/sysusers.d/isoterra.conf \
	usr/share/doc/isoterra/copyright usr/share/doc/isoterra/README.md.gz usr/share/doc/isoterra/KIOSK.md.gz \
	usr/share/doc/isoterra/PLATFORMS.md.gz; do
	[ -f "$INST_ROOT/$f" ] || miss="$miss /$f"
done
[ -z "$miss" ] && d13_ok "files in place" || d13_bad "missing:$miss ($(d13_in "$INST_ROOT" dpkg -L isoterra | tr '\n' ' '))"
grep -q "^ExecStart=/usr/bin/isoterra " "$INST_ROOT/usr/lib/systemd/system/isoterra-kiosk.service" &&
	grep -q -- "--config /etc/isoterra/kiosk.conf" "$INST_ROOT/usr/lib/systemd/system/isoterra-kiosk.service" &&
	d13_ok "unit runs /usr/bin/isoterra with /etc/isoterra/kiosk.conf" || d13_bad "unit's ExecStart"
[ -z "$(find "$INST_ROOT/etc/systemd/system" -name 'isoterra*' 2>/dev/null)" ] && d13_ok "unit not enabled" ||
	d13_bad "unit enabled: $(find "$INST_ROOT/etc/systemd/system" -name 'isoterra*')"
zcat "$INST_ROOT/usr/share/man/man1/isoterra.1.gz" 2>/dev/null | grep -q '^\.B \\-\\-octaves' &&
	d13_ok "man page lists the parameter table" || d13_bad "man page lacks --octaves"
# ---- 3b. the installed unit, run for real ---------------------------------------
# tests/vm/kiosk_unit.sh: the host's Debian kernel under QEMU boots systemd
# as PID 1 from an install chroot (plus udev, for the device nodes'
# groups); the packaged, enabled isoterra-kiosk.service drives the
# virtio-gpu display from its sandbox: READY=1, watchdog pings, frames on
# the display, SIGKILL -> restart, writes only to its state and cache
# folders.  Its checks count in this suite.  It runs once, on the Debian 12
# install (part 4: Mesa 22.3 compiles the guest's shaders in about half the
# time of trixie's Mesa 25 with an empty cache, and CI starts with one);
# ISOTERRA_DEB_VM=13 runs it on the Debian 13 install instead, 0 leaves it
# out; without QEMU or a kernel it is skipped, as the VM suite.
kiosk_vm() { # ROOT (mounted; left unmounted) CACHE-NAME
	t1=$(date +%s)
	if d13_install "$1" udev; then
		d13_cleanup # the guest mounts its own /proc, /sys, /dev
		rm -rf "$D13_LOGS/kiosk-vm"
		ISOTERRA_VM_CACHE_DIR=$D13/$2 sh "$D13_SRC/tests/vm/kiosk_unit.sh" "$1" "$D13_LOGS/kiosk-vm" \
			>"$D13_LOGS/kiosk-vm.log" 2>&1
		rc=$?
		line=$(grep -E '^kiosk_unit: [0-9]+ passed, [0-9]+ failed' "$D13_LOGS/kiosk-vm.log" | tail -1)
		d13_pass=$((d13_pass + $(echo "$line" | awk '{print $2+0}')))
		d13_fail=$((d13_fail + $(echo "$line" | awk '{print $4+0}')))
		if [ $rc -eq 0 ]; then
			grep -E '^ok: ' "$D13_LOGS/kiosk-vm.log" | while read -r l; do d13_log "  kiosk VM $l"; done
			d13_ok "the installed unit under systemd in the KMS VM ($2): $line ($(($(date +%s) - t1)) s)"
		elif [ $rc -eq 77 ]; then
			d13_log "kiosk unit VM test skipped: $(tail -1 "$D13_LOGS/kiosk-vm.log")"
		else
			grep -E '^(ok|FAIL): |serial:' "$D13_LOGS/kiosk-vm.log" | tail -40
			d13_bad "the installed unit in the KMS VM (log: $D13_LOGS/kiosk-vm.log)"
		fi
	else
		d13_bad "apt-get install udev in the install chroot"
	fi
}
[ "${ISOTERRA_DEB_VM:-12}" = 13 ] && kiosk_vm "$INST_ROOT" vm-kiosk
d13_cleanup
d13_rm "$INST_ROOT"

# ---- 4. Debian 12: built on the host, installed into a bookworm chroot --------
# The host is Debian 12 (the CI image): dpkg-checkbuilddeps checks that
# debian/control's Build-Depends are Debian 12 packages, installed here by
# tools/deps.sh; the build is nocheck (the host's own suites ran every test
# on this source).  On Debian 12 the GPIO knobs are on libgpiod 1.6
# (hal/gpiod_v1.c).  The packages are then installed, as in 3., into a
# fresh bookworm minbase chroot (its base tarball cached beside trixie's)
# and checked the same way.  With isoterra's Recommends (libgl1-mesa-dri:
# on Debian 12 libegl-mesa0 only recommends Mesa's drivers, llvmpipe among
# them; apt installs recommends by default).  ISOTERRA_DEB12=0 leaves
# this part out.
if [ "${ISOTERRA_DEB12:-1}" = 1 ]; then
	t1=$(date +%s)
	B12=$D13/d12pkg
	if [ "$(. /etc/os-release 2>/dev/null; echo "${VERSION_ID:-}")" != 12 ]; then
		d13_log "Debian 12 package: the host is not Debian 12: left out"
	elif ! command -v dpkg-buildpackage >/dev/null || ! command -v dh >/dev/null; then
		d13_bad "Debian 12 package: dpkg-dev or debhelper missing on the host (sh tools/deps.sh)"
	else
		d13_rm "$B12" && mkdir -p "$B12/isoterra-$VERSION"
		rel=${D13#"$D13_SRC"/}
		(cd "$D13_SRC" && tar --exclude=./.git --exclude='./build*' --exclude="./$rel" --exclude='./obj-*' \
			--exclude=./debian/.debhelper --exclude=./debian/isoterra --exclude=./debian/isoterra-geotiff \
			--exclude=./debian/tmp --exclude=./debian/files --exclude='./debian/*.substvars' \
			--exclude=./debian/debhelper-build-stamp -cf - .) | tar -C "$B12/isoterra-$VERSION" -xf -
		if ! (cd "$B12/isoterra-$VERSION" && dpkg-checkbuilddeps) >"$D13_LOGS/pkg12-builddeps.log" 2>&1; then
			d13_bad "Debian 12: $(cat "$D13_LOGS/pkg12-builddeps.log") (sh tools/deps.sh)"
		elif (cd "$B12/isoterra-$VERSION" && env -u MAKEFLAGS -u ASAN_OPTIONS -u LSAN_OPTIONS -u UBSAN_OPTIONS -u LD_PRELOAD \
			DEB_BUILD_OPTIONS="nocheck parallel=$(nproc)" dpkg-buildpackage -b -us -uc) >"$D13_LOGS/pkg12-build.log" 2>&1; then
			arch12=$(dpkg --print-architecture)
			d13_ok "Debian 12: dpkg-buildpackage -b (nocheck, $(($(date +%s) - t1)) s): $(cd "$B12" && ls ./*.deb | grep -v dbgsym | tr '\n' ' ')"
			grep -q "GPIO knobs: libgpiod 1\..*API v1" "$B12/isoterra-$VERSION/obj-"*/meson-logs/meson-log.txt &&
				d13_ok "Debian 12: GPIO knobs on libgpiod 1 (hal/gpiod_v1.c)" || d13_bad "Debian 12: GPIO knobs not on libgpiod 1"
			cp "$B12/isoterra_${VERSION}_$arch12.deb" "$D13_LOGS/isoterra_${VERSION}_${arch12}_deb12.deb"
			cp "$B12/isoterra-geotiff_${VERSION}_$arch12.deb" "$D13_LOGS/isoterra-geotiff_${VERSION}_${arch12}_deb12.deb"
			# the bookworm install chroot: chroot.sh's functions with the suite switched
			t1=$(date +%s)
			D13_SUITE=bookworm D13_BASE=$D13/bookworm-minbase.tar
			R12=$D13/install-root12
			if d13_base && d13_fresh "$R12" && d13_mount "$R12" && cp "$B12/isoterra_${VERSION}_$arch12.deb" \
				"$B12/isoterra-geotiff_${VERSION}_$arch12.deb" "$R12/tmp/" && d13_update "$R12" &&
				d13_retry d13_in "$R12" apt-get install -y -q "/tmp/isoterra_${VERSION}_$arch12.deb" \
					"/tmp/isoterra-geotiff_${VERSION}_$arch12.deb" $(dpkg-deb -f "$B12/isoterra_${VERSION}_$arch12.deb" Recommends |
					tr -d ,) >"$D13_LOGS/pkg12-install.log" 2>&1; then
				d13_ok "Debian 12: apt-get install of both packages ($(($(date +%s) - t1)) s)"
				d13_in "$R12" sh -c "cd /tmp && EGL_LOG_LEVEL=fatal isoterra --size 64x48 --grid 16 --out /tmp/x.png" \
					>"$D13_LOGS/pkg12-render.log" 2>&1 && [ -s "$R12/tmp/x.png" ] &&
					d13_ok "Debian 12: installed isoterra renders: $(tail -1 "$D13_LOGS/pkg12-render.log")" ||
					d13_bad "Debian 12: installed isoterra does not render: $(tail -3 "$D13_LOGS/pkg12-render.log")"
				pkg_checks "$R12" libgpiod.so.2
				[ "${ISOTERRA_DEB_VM:-12}" = 12 ] && kiosk_vm "$R12" vm-kiosk12
			else
				tail -20 "$D13_LOGS/pkg12-install.log" 2>/dev/null
				d13_bad "Debian 12: install chroot or apt-get install (log: $D13_LOGS/pkg12-install.log)"
			fi
			d13_cleanup
			d13_rm "$R12"
			D13_SUITE=trixie D13_BASE=$D13/trixie-minbase.tar
		else
			grep -E "error|Error" "$D13_LOGS/pkg12-build.log" | tail -20
			d13_bad "Debian 12: dpkg-buildpackage (log: $D13_LOGS/pkg12-build.log)"
		fi
		d13_rm "$B12"
	fi
fi

d13_log "package suite: $(($(date +%s) - t0)) s"
d13_summary package
[ $d13_fail -eq 0 ]
