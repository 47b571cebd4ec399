#!/bin/sh
# isoterra — the installed kiosk unit, run for real: the Debian kernel
# under QEMU (TCG, virtio-gpu) boots systemd as PID 1 from ROOT, a Debian
# root filesystem with the isoterra package installed (tools/debpkg.sh
# passes its install chroot), and the packaged isoterra-kiosk.service,
# enabled, drives the virtual display from its sandbox.  As root:
#
#   sh tests/vm/kiosk_unit.sh ROOT [RESULTS_DIR]
#
# ROOT is changed (a throwaway copy): the unit is enabled, with a drop-in
# for this machine (software rendering: MemoryDenyWriteExecute=no, see
# docs/KIOSK.md; a longer start and watchdog for TCG), a small
# /etc/isoterra/kiosk.conf, and the guest's test (kiosk_guest.sh) as a
# unit of its own.  Checked (the guest's lines and the host's): READY=1
# (active), watchdog pings (WatchdogTimestamp advances), frames advance
# (STATUS=) and are on the display (two screendumps differ from each other
# and from the console after the stop), a knob turn changes the picture (a
# gpio-sim chip, made before the unit starts, as the board's knobs: the
# pause button freezes the picture, then the encoder changes fov and the
# picture with it), SIGKILL -> restarted (NRestarts), the packaged unit's
# sandbox writes its state and cache folders only.
# Ends with "kiosk_unit: N passed, M failed"; exit 0 when all passed, 77
# when it cannot run here (no QEMU, kernel, busybox).
set -u
ROOT=${1:?usage: kiosk_unit.sh ROOT [RESULTS_DIR]}
here=$(cd "$(dirname "$0")" && pwd)
T=${2:-$(mktemp -d)}
mkdir -p "$T"
T=$(cd "$T" && pwd)
HALVM_CACHE=${ISOTERRA_VM_CACHE_DIR:-$T/cache}
HERE=$here
. "$here/hal_vm_lib.sh"
pass=0
fail=0
ok() { pass=$((pass + 1)); echo "ok: $*"; }
bad() { fail=$((fail + 1)); echo "FAIL: $*" >&2; }
finish() { echo "kiosk_unit: $pass passed, $fail failed"; [ $fail -eq 0 ]; exit $?; }
halvm_require
[ -x "$ROOT/lib/systemd/systemd" ] || halvm_skip "$ROOT has no systemd"
[ -x "$ROOT/usr/bin/isoterra" ] || halvm_skip "$ROOT has no /usr/bin/isoterra"
[ -x "$ROOT/usr/bin/udevadm" ] || halvm_skip "$ROOT has no udev (the device nodes' groups)"
command -v python3 >/dev/null || halvm_skip "python3 missing"
# gpio-sim, built out of tree as for tests/vm/gpio_knobs.sh and kept in the
# cache folder (the first build: a minute); in a subshell, as its missing
# prerequisites end the shell (halvm_skip): then the knob checks fail, the
# rest runs
GPIOSIM=$(halvm_gpio_sim_path)
if ! why=$(halvm_gpio_sim 2>&1) || [ ! -s "$GPIOSIM" ]; then
	bad "gpio-sim for the knobs: $(echo "$why" | tail -3)"
	GPIOSIM=
fi
t0=$(date +%s)

# ---- the root filesystem -------------------------------------------------------
W=320
H=240
[ -s "$ROOT/etc/machine-id" ] || od -An -tx1 -N16 /dev/urandom | tr -d ' \n' >"$ROOT/etc/machine-id"
echo >>"$ROOT/etc/machine-id"
mkdir -p "$ROOT/etc/systemd/journald.conf.d" "$ROOT/etc/systemd/system/multi-user.target.wants" \
	"$ROOT/etc/systemd/system/isoterra-kiosk.service.d" "$ROOT/usr/local/sbin"
printf '[Journal]\nStorage=volatile\n' >"$ROOT/etc/systemd/journald.conf.d/vm.conf"
ln -sf /usr/lib/systemd/system/isoterra-kiosk.service "$ROOT/etc/systemd/system/multi-user.target.wants/"
cat >"$ROOT/etc/systemd/system/isoterra-kiosk.service.d/vm.conf" <<CONF
# the test VM (tests/vm/kiosk_unit.sh): virtio-gpu without virgl, so Mesa's
# kms_swrast / llvmpipe, whose JIT needs writable+executable memory
# (docs/KIOSK.md); software rendering under TCG is slow: a longer start
# and watchdog
[Service]
MemoryDenyWriteExecute=no
TimeoutStartSec=400
WatchdogSec=20
CONF
cat >"$ROOT/etc/isoterra/kiosk.conf" <<CONF
# tests/vm/kiosk_unit.sh: tiny work (software rendering under TCG)
mode = ${W}x$H
grid = 16
seed = 7
ao_rays = 0
# the knobs (the guest's gpio-sim chip "knobs", isoterra-vmtest-gpio
# below): encoder 2 (lines 0, 1) changes fov, one step a detent; button 1
# (line 2, active-low) pauses.  The sim's pulls are the board's resistors
# (bias as_is); no OSD: the picture changes by the parameter alone.  The
# knob log, in the unit's state folder, tells the guest's test when a
# change is taken
gpio_chip = knobs
enc2_a = 0
enc2_b = 1
enc_accel_max = 1
button1_line = 2
button1_action = pause
button_bias = as_is
knob_params = fov
knob_log = /var/lib/isoterra/knob.log
osd = false
CONF
# the gpiochip's node as board images give it (Raspberry Pi OS's
# 99-com.rules): group gpio, mode 0660.  The package's postinst adds user
# isoterra to a gpio group where one exists (tools/debpkg.sh made one and
# ran dpkg-reconfigure before this; made here where it did not)
mkdir -p "$ROOT/etc/udev/rules.d"
echo 'SUBSYSTEM=="gpio", KERNEL=="gpiochip*", GROUP="gpio", MODE="0660"' >"$ROOT/etc/udev/rules.d/60-isoterra-vm-gpio.rules"
if ! grep -q '^gpio:.*[:,]isoterra\(,\|$\)' "$ROOT/etc/group"; then
	grep -q '^gpio:' "$ROOT/etc/group" || chroot "$ROOT" groupadd -r gpio
	env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin DEBIAN_FRONTEND=noninteractive chroot "$ROOT" dpkg-reconfigure isoterra \
		>/dev/null 2>&1
	grep -q '^gpio:.*[:,]isoterra\(,\|$\)' "$ROOT/etc/group" || bad "user isoterra not in group gpio: $(grep '^gpio:' "$ROOT/etc/group")"
fi
# the chip, before the unit starts (isoterra-vmtest-gpio.service): 4 lines
# labelled "knobs", at rest (the encoder's phases low, the button
# released: high), the node's group from the rule above (udevadm settle);
# its name and sysfs folder for the guest's test in /vmtest/gpio.env
cat >"$ROOT/usr/local/sbin/isoterra-vmtest-gpio" <<'GPIO'
#!/bin/sh
exec >/vmtest/gpio.log 2>&1
C=/sys/kernel/config
mountpoint -q $C || mount -t configfs none $C
D=$C/gpio-sim/knobs
if ! mkdir -p $D/bank0 || ! echo 4 >$D/bank0/num_lines || ! echo knobs >$D/bank0/label || ! echo 1 >$D/live; then
	echo "gpio-sim: cannot create the chip: $(ls $C 2>&1)"
	exit 1
fi
CHIP=$(cat $D/bank0/chip_name)
SYS=/sys/devices/platform/$(cat $D/dev_name)/$CHIP
for l in 0 1; do echo pull-down >"$SYS/sim_gpio$l/pull"; done
echo pull-up >"$SYS/sim_gpio2/pull"
udevadm settle
printf 'CHIP=%s\nSYS=%s\n' "$CHIP" "$SYS" >/vmtest/gpio.env
echo "gpio-sim: $CHIP: $(ls -l "/dev/$CHIP")"
GPIO
cat >"$ROOT/etc/systemd/system/isoterra-vmtest-gpio.service" <<CONF
[Unit]
Description=isoterra kiosk-unit VM test: the knobs' gpio-sim chip
After=systemd-udevd.service sys-kernel-config.mount
Before=isoterra-kiosk.service
[Service]
Type=oneshot
RemainAfterExit=yes
ExecStart=/bin/sh /usr/local/sbin/isoterra-vmtest-gpio
[Install]
WantedBy=multi-user.target
CONF
ln -sf /etc/systemd/system/isoterra-vmtest-gpio.service "$ROOT/etc/systemd/system/multi-user.target.wants/"
# the sandbox's writes: copies of the packaged unit (its sandbox whole,
# software rendering allowed as above) that run one headless frame to
# --out PATH (isoterra-wtest-N), or a shell that tries to create a file in
# each folder (isoterra-wprobe)
wunit() { # NAME EXECSTART
	sed -e 's/^Type=notify/Type=oneshot/' -e '/^WatchdogSec/d' -e '/^Restart/d' -e '/^TTYPath/d' \
		-e '/^StandardInput/d' -e '/^Conflicts/d' -e '/^\[Install\]/,$d' -e '/^[[:space:]]*--config /d' \
		-e 's/^MemoryDenyWriteExecute=yes/MemoryDenyWriteExecute=no/' -e "s|^ExecStart=.*|ExecStart=$2|" \
		"$ROOT/usr/lib/systemd/system/isoterra-kiosk.service" >"$ROOT/etc/systemd/system/$1.service"
}
for t in 1:/var/lib/isoterra/w.png 2:/etc/isoterra-open/w.png; do
	wunit "isoterra-wtest-${t%%:*}" "/usr/bin/isoterra --platform surfaceless --size 32x24 --grid 8 --count 1 --out ${t#*:}"
	rm -f "$ROOT${t#*:}"
done
cat >"$ROOT/usr/local/sbin/isoterra-wprobe" <<'PROBE'
#!/bin/sh
for d in /var/lib/isoterra /var/cache/isoterra /etc /etc/isoterra /usr/local /var/log /root /etc/isoterra-open \
	/usr/local/isoterra-open /var/lib/isoterra-open /srv/isoterra-open /run/lock /home/isoterra-open /var/tmp /tmp /dev/shm; do
	if err=$( (: >"$d/isoterra-wprobe") 2>&1); then echo "writable $d: created $d/isoterra-wprobe"
	else echo "refused $d: ${err##*: }"; fi
done
PROBE
wunit isoterra-wprobe "/bin/sh /usr/local/sbin/isoterra-wprobe"
# folders anyone may write to: only the sandbox keeps the unit out
for d in /etc/isoterra-open /usr/local/isoterra-open /var/lib/isoterra-open /srv/isoterra-open /home/isoterra-open; do
	mkdir -p "$ROOT$d" && chmod 1777 "$ROOT$d" && rm -f "$ROOT$d/isoterra-wprobe"
done
rm -f "$ROOT/var/tmp/isoterra-wprobe" "$ROOT/tmp/isoterra-wprobe" "$ROOT/var/lib/isoterra/knob.log"
cp "$here/kiosk_guest.sh" "$ROOT/usr/local/sbin/isoterra-vmtest"
cat >"$ROOT/etc/systemd/system/isoterra-vmtest.service" <<CONF
[Unit]
Description=isoterra kiosk-unit VM test (tests/vm/kiosk_guest.sh)
[Service]
Type=oneshot
ExecStart=/bin/sh /usr/local/sbin/isoterra-vmtest
StandardOutput=journal+console
[Install]
WantedBy=multi-user.target
CONF
ln -sf /etc/systemd/system/isoterra-vmtest.service "$ROOT/etc/systemd/system/multi-user.target.wants/"
rm -rf "$ROOT/vmtest" && mkdir -p "$ROOT/vmtest"
# Mesa's shader cache for the guest's CPU, kept between runs (a cold one
# costs minutes under TCG): copied into the unit's cache folder and back
MESA_KEEP=${ISOTERRA_VM_MESA_CACHE:-$HALVM_CACHE/kiosk-mesa}
# (mesa_shader_cache: Mesa 22's folder; mesa_shader_cache_db: Mesa 25's;
# systemd gives them to the unit's user at its start)
mkdir -p "$MESA_KEEP" "$ROOT/var/cache/isoterra"
rm -rf "$ROOT/var/cache/isoterra/"mesa_shader_cache*
for d in "$MESA_KEEP"/mesa_shader_cache*; do
	[ -d "$d" ] && cp -a "$d" "$ROOT/var/cache/isoterra/"
done

# ---- the VM ----------------------------------------------------------------------
# the modules: virtio, 9p, the display, and configfs + gpio-sim for the
# knobs (the root has no /lib/modules of this kernel); rebuilt when the
# list, kiosk_init, mkinitramfs.sh or the module changes
INITRD=$HALVM_CACHE/kiosk-initramfs-$HALVM_REL.cpio.gz
mods="virtio_pci 9pnet_virtio 9p virtio_gpu${GPIOSIM:+ configfs $GPIOSIM}"
if [ ! -s "$INITRD" ] || [ "$(cat "$INITRD.mods" 2>/dev/null)" != "$mods" ] || [ "$here/kiosk_init" -nt "$INITRD" ] ||
	[ "$here/mkinitramfs.sh" -nt "$INITRD" ] || { [ -n "$GPIOSIM" ] && [ "$GPIOSIM" -nt "$INITRD" ]; }; then
	# shellcheck disable=SC2086 # a word list
	sh "$here/mkinitramfs.sh" "$INITRD" "$HALVM_REL" "$here/kiosk_init" $mods >/dev/null || { bad "initramfs"; finish; }
	echo "$mods" >"$INITRD.mods"
fi
alive() { kill -0 "$1" 2>/dev/null; }
rm -f "$T"/*.ppm "$T/mon.sock"
qemu-system-x86_64 -machine pc -cpu max -smp 2 -m 1536 -no-reboot \
	-display none -vga none -serial "file:$T/serial.log" \
	-monitor "unix:$T/mon.sock,server,nowait" \
	-device virtio-gpu-pci,xres=$W,yres=$H \
	-virtfs "local,path=$ROOT,mount_tag=root,security_model=passthrough,multidevs=remap" \
	-kernel "/boot/vmlinuz-$HALVM_REL" -initrd "$INITRD" \
	-append "console=ttyS0 panic=-1 loglevel=3 consoleblank=0 vt.global_cursor_default=0 systemd.firstboot=0 systemd.show_status=0" \
	>"$T/qemu.log" 2>&1 &
QPID=$!
# a cold Mesa shader cache on a loaded 2-core machine: ~15 min seen
LIMIT=${ISOTERRA_VM_TIMEOUT:-1500}
while alive "$QPID"; do
	for req in "$ROOT/vmtest"/req-*; do
		[ -e "$req" ] || continue
		name=${req##*/req-}
		[ -e "$ROOT/vmtest/ack-$name" ] && continue
		python3 "$here/hmp.py" "$T/mon.sock" "screendump $T/$name.ppm" >"$T/hmp-$name.log" 2>&1 ||
			echo "screendump $name: $(cat "$T/hmp-$name.log")" >&2
		echo "screendump $name at $(($(date +%s) - t0)) s"
		: >"$ROOT/vmtest/ack-$name"
	done
	if [ $(($(date +%s) - t0)) -gt "$LIMIT" ]; then
		bad "VM still running after $LIMIT s; killed. serial: $(tail -5 "$T/serial.log")"
		kill -KILL "$QPID"
		break
	fi
	sleep 0.2
done
wait "$QPID" 2>/dev/null
echo "VM ran $(($(date +%s) - t0)) s"
cp "$ROOT/vmtest/"*.log "$T/" 2>/dev/null
rm -rf "$MESA_KEEP.new" && mkdir -p "$MESA_KEEP.new" &&
	cp -a "$ROOT/var/cache/isoterra/"mesa_shader_cache* "$MESA_KEEP.new/" 2>/dev/null &&
	rm -rf "$MESA_KEEP" && mv "$MESA_KEEP.new" "$MESA_KEEP"

# ---- checks ----------------------------------------------------------------------
grep -v '^$' "$T/serial.log" | tail -8 | sed 's/^/  serial: /'
[ -e "$ROOT/vmtest/done" ] || bad "the guest's test did not finish (serial: $(tail -3 "$T/serial.log"))"
while read -r l; do
	case "$l" in
	ok:*) ok "${l#ok: }" ;;
	FAIL:*) bad "${l#FAIL: }" ;;
	*) echo "  $l" ;;
	esac
done <"$ROOT/vmtest/guest.log"
# the display: two frames of the kiosk, different (the orbit moves) and
# not the console (after the stop); terrain colours, not one flat colour.
# Then the knob: two frames while paused, the same to the byte (the
# picture is frozen), and one after the encoder's turn, different (fov)
python3 - "$T" "$here" <<'PY' >"$T/shots.log" 2>&1
import sys
sys.dont_write_bytecode = True  # nothing written into the source tree
sys.path.insert(0, sys.argv[2])
from ppm import ppm, diff
T = sys.argv[1]
a, b, c = (ppm('%s/%s.ppm' % (T, n)) for n in ('kiosk-a', 'kiosk-b', 'console'))
colours = len(set(a[2][i:i + 3] for i in range(0, len(a[2]), 3)))
print("kiosk %dx%d, %d colours; mean |a-b| %.2f, |a-console| %.2f" % (a[0], a[1], colours, diff(a, b), diff(a, c)))
sys.exit(0 if colours > 50 and diff(a, b) > 0.5 and diff(a, c) > 5 else 1)
PY
if [ $? -eq 0 ]; then
	ok "on the display: $(cat "$T/shots.log")"
else
	bad "the display: $(tail -3 "$T/shots.log")"
fi
if python3 - "$T" "$here" <<'PY' >"$T/knob-shots.log" 2>&1; then
import sys
sys.dont_write_bytecode = True  # nothing written into the source tree
sys.path.insert(0, sys.argv[2])
from ppm import ppm, diff
T = sys.argv[1]
p1, p2, k = (ppm('%s/%s.ppm' % (T, n)) for n in ('paused-a', 'paused-b', 'knob'))
print("paused: |a-b| %.2f (%s); after the turn: |paused-knob| %.2f" %
      (diff(p1, p2), "the same" if p1 == p2 else "different", diff(p2, k)))
sys.exit(0 if p1 == p2 and diff(p2, k) > 0.5 else 1)
PY
	ok "the knob on the display: $(cat "$T/knob-shots.log")"
else
	bad "the knob on the display: $(tail -3 "$T/knob-shots.log")"
fi
echo "kiosk_unit: $(($(date +%s) - t0)) s; results in $T"
finish
