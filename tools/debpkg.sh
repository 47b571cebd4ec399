#!/bin/sh
# isoterra — the Debian package, built and installed on Debian 13.  As root:
#
#   sh tools/debpkg.sh
#
# 1. Build: `dpkg-buildpackage -b -us -uc` in a chroot that has only the
#    base system and debian/control's Build-Depends (apt-get build-dep), so
#    a missing build dependency fails here.  That chroot (build-d13/pkg-root)
#    is cached and made again from the base tarball when debian/control
#    changes.  The package's own tests run (debian/rules: every suite but
#    vm and display); ISOTERRA_DEB_NOCHECK=1 skips them.
# 2. lintian, in the build chroot of tools/debian13.sh: errors and warnings
#    fail (overrides, each with its reason, live in debian/).
# 3. Install: a fresh minbase chroot, `apt-get install ./isoterra_*.deb`
#    (dependencies from the archive, no recommends), then the installed
#    binary renders a frame that must equal the one the source build
#    renders, the example /etc/isoterra/kiosk.conf parses, the man page,
#    unit (not enabled), conffile and documentation are in place.
# Ends with "== debian13 package: N passed, M failed".  The .deb, .changes
# and lintian's report are left in build-d13/logs/.
set -u
. "$(dirname "$0")/chroot.sh"

PKG_ROOT=$D13/pkg-root
INST_ROOT=$D13/install-root
VERSION=$(sed -n '1s/^isoterra (\([^)]*\)).*/\1/p' "$D13_SRC/debian/changelog")

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
[ -s "$PKG_ROOT/pkg/$deb" ] && d13_ok "$deb" || fail "no $deb"
cp "$PKG_ROOT/pkg/$deb" "$PKG_ROOT/pkg/isoterra_${VERSION}_$arch.changes" "$D13_LOGS/"
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
cp "$PKG_ROOT/pkg/$deb" "$INST_ROOT/tmp/"
d13_update "$INST_ROOT" || fail "apt-get update"
if d13_retry d13_in "$INST_ROOT" apt-get install -y -q "/tmp/$deb" >"$D13_LOGS/pkg-install.log" 2>&1; then
	d13_ok "apt-get install ./$deb: $(grep -cE '^(Unpacking|Preparing to unpack)' "$D13_LOGS/pkg-install.log") unpack steps ($(($(date +%s) - t1)) s)"
else
	tail -30 "$D13_LOGS/pkg-install.log"
	fail "apt-get install ./$deb"
fi
[ "$(d13_in "$INST_ROOT" dpkg-query -W -f '${db:Status-Status}' isoterra)" = installed ] && d13_ok "isoterra installed" ||
	d13_bad "isoterra not installed"
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
for f in usr/bin/isoterra usr/share/man/man1/isoterra.1.gz usr/lib/systemd/system/isoterra-kiosk.service \
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
d13_cleanup
d13_rm "$INST_ROOT"

d13_log "package suite: $(($(date +%s) - t0)) s"
d13_summary package
[ $d13_fail -eq 0 ]
