# isoterra — Debian 13 chroots for CI (sourced by tools/debian13.sh,
# tools/arm64.sh and tools/debpkg.sh; POSIX sh, run as root).
#
# Cache, under $D13 (default build-d13/ in the source tree, ignored by git;
# ISOTERRA_D13_DIR moves it, e.g. to /var/cache/isoterra):
#   trixie-minbase.tar  debootstrap --variant=minbase trixie, untouched;
#                       written to a temporary name and renamed when whole
#   root/               the build chroot: that base plus the packages each
#                       suite asks for (d13_install adds them incrementally);
#                       rebuilt from the tarball when missing or broken
#   apt-archives/       downloaded .debs, shared by every chroot (a fresh
#                       install chroot downloads nothing twice)
#   logs/               what the suites leave for the host (test logs, images)
# Kept between runs on one machine; `sh tools/debian13.sh clean` drops it.
#
# Mounts (/proc, /sys, /dev, the apt cache) exist only while a suite runs:
# d13_mount registers an EXIT/INT/TERM trap that unmounts them all, in
# reverse order, and nothing under a chroot is ever deleted while mounted.
# Network steps (debootstrap, apt-get update/install) are retried once.

D13_SRC=$(cd "$(dirname "$0")/.." && pwd)
D13=${ISOTERRA_D13_DIR:-$D13_SRC/build-d13}
D13_MIRROR=${ISOTERRA_D13_MIRROR:-http://deb.debian.org/debian}
D13_SUITE=trixie
D13_BASE=$D13/$D13_SUITE-minbase.tar
D13_ROOT=$D13/root
D13_LOGS=$D13/logs
D13_MOUNTS=""     # mount points, newest first
d13_pass=0
d13_fail=0

d13_log() { echo "[$(date +%H:%M:%S)] $*"; }
d13_ok() { d13_pass=$((d13_pass + 1)); d13_log "ok: $*"; }
d13_bad() { d13_fail=$((d13_fail + 1)); d13_log "FAIL: $*" >&2; }
# the suite's line for tools/test-all.sh (it adds these to its totals)
d13_summary() { echo "== debian13 $1: $d13_pass passed, $d13_fail failed"; }

# run "$@" and, when it fails, once more after a pause (network steps)
d13_retry() {
	"$@" && return 0
	d13_log "failed, retrying once in 10 s: $*"
	sleep 10
	"$@"
}

d13_need_root() {
	if [ "$(id -u)" -ne 0 ]; then
		echo "$0: needs root (debootstrap, chroot, mount): sudo sh $0 $*" >&2
		exit 2
	fi
	for t in debootstrap chroot mount umount tar flock; do
		command -v "$t" >/dev/null 2>&1 || { echo "$0: '$t' missing (sudo sh tools/deps.sh)" >&2; exit 2; }
	done
}

# one suite at a time per cache folder
d13_lock() {
	mkdir -p "$D13" "$D13_LOGS"
	exec 9>"$D13/.lock"
	flock -w 3600 9 || { echo "$0: $D13 is locked by another run" >&2; exit 2; }
}

# mounts under $1 (from /proc/mounts), one a line
d13_mounts_under() {
	awk -v p="$1" '$2 == p || index($2, p "/") == 1 { print $2 }' /proc/mounts
}

# unmounts everything under $1, deepest first; lazily when busy
d13_umount_all() {
	for m in $(d13_mounts_under "$1" | sort -r); do
		umount "$m" 2>/dev/null || umount -l "$m" || d13_log "cannot unmount $m"
	done
}

# rm -rf, refused while anything under it is mounted
d13_rm() {
	[ -e "$1" ] || return 0
	d13_umount_all "$1"
	if [ -n "$(d13_mounts_under "$1")" ]; then
		echo "$0: refusing to delete $1: still mounted: $(d13_mounts_under "$1")" >&2
		return 1
	fi
	rm -rf --one-file-system "$1"
}

d13_cleanup() {
	for m in $D13_MOUNTS; do
		[ -n "$(awk -v p="$m" '$2 == p' /proc/mounts)" ] || continue # already undone
		umount "$m" 2>/dev/null || umount -l "$m" 2>/dev/null || d13_log "cannot unmount $m"
	done
	D13_MOUNTS=""
}

# d13_mount ROOT: /proc, /sys, /dev (the host's: null, zero, urandom, dri
# when there is one), the apt cache, resolv.conf; unmounted at exit
d13_mount() {
	r=$1
	d13_umount_all "$r" # left over from an interrupted run
	trap 'd13_cleanup' EXIT
	trap 'd13_cleanup; exit 130' INT
	trap 'd13_cleanup; exit 143' TERM
	mkdir -p "$r/proc" "$r/sys" "$r/dev" "$r/var/cache/apt/archives" "$D13/apt-archives/partial"
	mount -t proc proc "$r/proc" && D13_MOUNTS="$r/proc $D13_MOUNTS"
	mount --bind /sys "$r/sys" && D13_MOUNTS="$r/sys $D13_MOUNTS"
	mount --bind /dev "$r/dev" && D13_MOUNTS="$r/dev $D13_MOUNTS"
	# pseudo-terminals (a test drives the progress bar through script(1))
	if [ -d /dev/pts ]; then
		mount --bind /dev/pts "$r/dev/pts" && D13_MOUNTS="$r/dev/pts $D13_MOUNTS"
	fi
	mount --bind "$D13/apt-archives" "$r/var/cache/apt/archives" && D13_MOUNTS="$r/var/cache/apt/archives $D13_MOUNTS"
	[ -r /etc/resolv.conf ] && cat /etc/resolv.conf >"$r/etc/resolv.conf" 2>/dev/null
	[ -e "$r/proc/self" ] && [ -e "$r/dev/null" ] || { echo "$0: mounting /proc, /dev in $r failed" >&2; return 1; }
}

# d13_in ROOT COMMAND...: a clean environment (nothing of the host's
# sanitizer or test settings leaks in)
d13_in() {
	r=$1
	shift
	env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin HOME=/root LC_ALL=C.UTF-8 TERM=dumb \
		DEBIAN_FRONTEND=noninteractive chroot "$r" "$@"
}

# the pristine base tarball
d13_base() {
	if [ -s "$D13_BASE" ]; then
		return 0
	fi
	t=$D13/base.tmp
	d13_rm "$t" || return 1
	d13_log "debootstrap --variant=minbase $D13_SUITE ($D13_MIRROR)"
	if ! debootstrap --variant=minbase "$D13_SUITE" "$t" "$D13_MIRROR" >"$D13_LOGS/debootstrap.log" 2>&1; then
		tail -5 "$D13_LOGS/debootstrap.log"
		d13_rm "$t" || return 1
		d13_log "debootstrap failed, retrying once"
		sleep 10
		debootstrap --variant=minbase "$D13_SUITE" "$t" "$D13_MIRROR" >"$D13_LOGS/debootstrap.log" 2>&1 ||
			{ tail -20 "$D13_LOGS/debootstrap.log"; d13_rm "$t"; return 1; }
	fi
	# apt in the chroots: no service starts, no recommends, keep downloads
	printf '#!/bin/sh\nexit 101\n' >"$t/usr/sbin/policy-rc.d"
	chmod 755 "$t/usr/sbin/policy-rc.d"
	cat >"$t/etc/apt/apt.conf.d/90isoterra" <<-EOF
		APT::Install-Recommends "false";
		APT::Keep-Downloaded-Packages "true";
		Acquire::Retries "3";
		Dpkg::Use-Pty "false";
	EOF
	rm -f "$t/var/cache/apt/archives/"*.deb
	tar -C "$t" --numeric-owner -cf "$D13_BASE.tmp" . && mv "$D13_BASE.tmp" "$D13_BASE" || return 1
	d13_rm "$t"
}

# d13_fresh DIR: a new chroot from the base tarball
d13_fresh() {
	d13_rm "$1" || return 1
	mkdir -p "$1" && tar -C "$1" --numeric-owner -xf "$D13_BASE"
}

# the build chroot, healthy: dpkg consistent, the base stamp matching
d13_root() {
	d13_base || return 1
	if [ -f "$D13_ROOT/.isoterra-root" ] && [ "$D13_ROOT/.isoterra-root" -nt "$D13_BASE" ] &&
		d13_in "$D13_ROOT" /bin/true 2>/dev/null && [ -z "$(d13_in "$D13_ROOT" dpkg --audit 2>&1)" ]; then
		return 0
	fi
	d13_log "build chroot missing or broken: new one from the base tarball"
	d13_fresh "$D13_ROOT" && touch "$D13_ROOT/.isoterra-root"
}

# d13_install ROOT PACKAGES...: apt-get install what is not installed yet
# (the first call of a run also updates the package lists)
d13_install() {
	r=$1
	shift
	missing=""
	for p in "$@"; do
		d13_in "$r" dpkg-query -W -f '${db:Status-Status}\n' "$p" 2>/dev/null | grep -qx installed || missing="$missing $p"
	done
	[ -n "$missing" ] || return 0
	if [ ! -f "$r/.isoterra-updated" ] || [ -n "$(find "$r/.isoterra-updated" -mmin +360 2>/dev/null)" ]; then
		d13_update "$r" || return 1
	fi
	d13_log "apt-get install$missing"
	# shellcheck disable=SC2086 # a word list
	d13_in "$r" apt-get install -y -q $missing >"$D13_LOGS/apt-install.log" 2>&1 && return 0
	# a transient failure, or package lists older than the archive: once more
	d13_log "apt-get install failed: updating the lists and retrying once"
	sleep 10
	d13_update "$r" || return 1
	# shellcheck disable=SC2086
	d13_in "$r" apt-get install -y -q $missing >"$D13_LOGS/apt-install.log" 2>&1 ||
		{ tail -30 "$D13_LOGS/apt-install.log"; return 1; }
}

d13_update() {
	d13_retry d13_in "$1" apt-get update -q >"$D13_LOGS/apt-update.log" 2>&1 ||
		{ tail -20 "$D13_LOGS/apt-update.log"; return 1; }
	touch "$1/.isoterra-updated"
}

# d13_copy_src ROOT [DIR]: the source tree, copied into ROOT/DIR (default
# /src; not bind-mounted: packaging writes into it); unchanged files keep
# their times, so warm builds are incremental
d13_copy_src() {
	r=$1
	dst=$r${2:-/src}
	d13_rm "$dst.new" || return 1
	mkdir -p "$dst.new"
	rel=${D13#"$D13_SRC"/}
	(cd "$D13_SRC" && tar --exclude=./.git --exclude='./build*' --exclude="./$rel" --exclude='./obj-*' \
		--exclude=./debian/.debhelper --exclude=./debian/isoterra --exclude=./debian/files \
		--exclude='./debian/*.substvars' --exclude=./debian/debhelper-build-stamp -cf - .) |
		tar -C "$dst.new" -xf - || return 1
	d13_rm "$dst" && mv "$dst.new" "$dst"
}
