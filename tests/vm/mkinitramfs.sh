#!/bin/sh
# isoterra — build a QEMU test initramfs: busybox-static, the kernel
# modules named (with their dependencies, as `modprobe --show-depends`
# lists them for this kernel release, in load order: /mods/order) and INIT
# as /init.  Used by the KMS test (init: tests/vm/init, + virtio_gpu) and
# the hardware-layer tests (init: tests/vm/hal_init).
#   mkinitramfs.sh OUT.cpio.gz KERNEL_RELEASE INIT MODULE...
# A MODULE that is a path to a .ko file (a module built out of tree, e.g.
# gpio-sim: tests/vm/hal_vm_lib.sh) is taken as it is, in its place in the
# order, without dependencies: name the modules it needs before it.
set -eu
[ $# -ge 4 ] || { echo "usage: mkinitramfs.sh OUT.cpio.gz KERNEL_RELEASE INIT MODULE..." >&2; exit 2; }
out=$1
rel=$2
init=$3
shift 3
busybox=$(command -v busybox || echo /bin/busybox)
[ -x "$busybox" ] || { echo "mkinitramfs: busybox not found (apt-get install busybox-static)" >&2; exit 1; }
# a dynamically linked busybox would need its libraries in the initramfs
# (ldd fails on a static executable)
if ldd "$busybox" >/dev/null 2>&1; then
	echo "mkinitramfs: $busybox is dynamically linked (apt-get install busybox-static)" >&2
	exit 1
fi
[ -d "/lib/modules/$rel" ] || { echo "mkinitramfs: /lib/modules/$rel missing (apt-get install linux-image-amd64)" >&2; exit 1; }
d=$(mktemp -d)
trap 'rm -rf "$d"' EXIT
mkdir -p "$d/bin" "$d/proc" "$d/sys" "$d/dev" "$d/host" "$d/mods"
cp "$busybox" "$d/bin/busybox"
for m in "$@"; do
	case "$m" in
	/*.ko)
		[ -s "$m" ] || { echo "mkinitramfs: no module file $m" >&2; exit 1; }
		echo "insmod $m"
		;;
	*) modprobe -S "$rel" --show-depends "$m" || { echo "mkinitramfs: no module $m for $rel" >&2; exit 1; } ;;
	esac
done | awk '$1 == "insmod" && !seen[$2]++ { print $2 }' >"$d/list"
while read -r ko; do
	name=$(basename "$ko")
	case "$name" in
	*.ko) cp "$ko" "$d/mods/$name" ;;
	*.ko.xz) name=${name%.xz}; xz -dc "$ko" >"$d/mods/$name" ;;
	*.ko.zst) name=${name%.zst}; zstd -qdc "$ko" >"$d/mods/$name" ;;
	*.ko.gz) name=${name%.gz}; gzip -dc "$ko" >"$d/mods/$name" ;;
	*) echo "mkinitramfs: unknown module file $ko" >&2; exit 1 ;;
	esac
	echo "$name" >>"$d/mods/order"
done <"$d/list"
rm "$d/list"
cp "$init" "$d/init"
chmod 755 "$d/init"
(cd "$d" && find . | cpio -o -H newc --quiet | gzip -1) >"$out.tmp"
mv "$out.tmp" "$out"
echo "mkinitramfs: $out ($(wc -l <"$d/mods/order") modules for $rel)"
