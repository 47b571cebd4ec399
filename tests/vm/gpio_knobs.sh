#!/bin/sh
# isoterra — GPIO knobs against the real kernel: Debian's kernel under QEMU,
# gpio-sim (built out of tree) as the gpiochip, and isoterra itself rendering
# headless in the guest.  The guest part (gpio_knobs_guest.sh) turns
# encoder 2 and encoder 1 through the Gray sequence and presses the buttons
# by writing the lines' sysfs "pull"; the app's knob log must show exactly
# the expected parameter steps.  Then the chip is taken away (live = 0) and
# brought back, and finally removed (rmdir): the app must keep rendering,
# report it, and work again when the chip is back.  Last the chip comes
# back with one line held by a kernel hog: the app reports the busy line,
# retries, and is back once the hog is gone.  A crash leaves a core
# in the results folder, whose backtrace is printed here.
# The same run takes keys from a virtual evdev keyboard (uinput, made by
# hal_probe keys): --keyboard evdev drives the same actions, and the
# keyboard going away is reported.
# usage: gpio_knobs.sh ISOTERRA HAL_PROBE BUILD_DIR [sanitize]
#
# ISOTERRA_GUEST_ROOT=DIR runs ISOTERRA and HAL_PROBE, paths inside DIR, in
# a chroot of DIR in the guest (DIR is a host folder: the guest sees the
# host's / over 9p), e.g. the Debian 13 chroot's build with libgpiod 2
# (tools/debian13.sh): the same kernel, gpio-sim and test, another libgpiod.
# ISOTERRA_EXPECT_LIBGPIOD=libgpiod.so.N adds a check that the running app
# has that library mapped.  Give such a run its own ISOTERRA_VM_CACHE (its
# Mesa is another).  BUILD_DIR holds the caches and the results folder.
BIN=$1
PROBE=$2
BUILD=$3
[ "${4:-none}" = none ] || { echo "SKIP: VM tests run in the plain build only (this one: $4)"; exit 77; }
HERE=$(cd "$(dirname "$0")" && pwd)
HALVM_CACHE="$BUILD/hal-vm-cache"
. "$HERE/hal_vm_lib.sh"
ROOT=${ISOTERRA_GUEST_ROOT:-}
if [ -n "$ROOT" ]; then
	ROOT=$(cd "$ROOT" && pwd) || { echo "FAIL: guest root $ISOTERRA_GUEST_ROOT missing"; exit 1; }
	for f in "$BIN" "$PROBE"; do
		[ -x "$ROOT$f" ] || { echo "FAIL: $f is not an executable in $ROOT"; exit 1; }
	done
fi
halvm_require
halvm_gpio_sim || { echo "FAIL: building gpio-sim failed"; exit 1; }
halvm_initramfs || { echo "FAIL: building the initramfs failed"; exit 1; }
halvm_mesa_cache
RES=$(mktemp -d "$BUILD/hal-vm-gpio.XXXXXX")
[ -n "$ISOTERRA_KEEP" ] && echo "results kept in $RES" || trap 'rm -rf "$RES"' EXIT
cat >"$RES/env.sh" <<ENV
BIN=$BIN
PROBE=$PROBE
GPIOSIM=$HALVM_GPIOSIM
GUEST_ROOT=$ROOT
EXPECT_LIBGPIOD=${ISOTERRA_EXPECT_LIBGPIOD:-}
ENV
halvm_env "$RES"
# A guest kernel oops is the kernel's fault, not the app's (seen in CI on
# Debian 12's 6.1.0-57: faults in a line request's kmalloc and in
# request_threaded_irq's /proc entry, after this test had removed chips
# with lines still requested, as it does on purpose; twice in one run, so
# the retry alone did not hold: the simulator's teardown no longer frees
# such a line's interrupt, hal_vm_lib.sh halvm_gpio_sim): said, and the VM
# booted once more; a second oops fails the test.
for try in 1 2; do
	t0=$(date +%s)
	halvm_boot "$RES" "$HERE/gpio_knobs_guest.sh" "${ISOTERRA_VM_TIMEOUT:-840}"
	echo "VM: $(($(date +%s) - t0)) s (kernel $HALVM_REL, TCG, shader cache ${HALVM_MESA_CACHE:-none}${ROOT:+, app in $ROOT})"
	oops=$(halvm_oops "$RES") || break
	echo "guest kernel oops (boot $try), not the app's:"
	echo "$oops" | sed 's/^/  /'
	[ "$try" = 2 ] && break
	find "$RES" -mindepth 1 ! -name env.sh -exec rm -rf {} + # the first boot's results
	echo "booting again"
done
pass=$(grep -c '^ok' "$RES/console.log")
fail=$(grep -c '^FAIL' "$RES/console.log")
if ! grep -q "HALVM-EXIT 0" "$RES/console.log"; then
	echo "FAIL: the guest test failed; console:"
	tail -60 "$RES/console.log"
	[ -f "$RES/app.log" ] && { echo "--- app log:"; tail -30 "$RES/app.log"; }
	halvm_cores "$RES" "$BIN" "$ROOT"
	echo "gpio_knobs: $pass passed, $((fail > 0 ? fail : 1)) failed"
	exit 1
fi
grep -E "^(ok|FAIL|guest)" "$RES/console.log" | tr -d '\r'
echo "gpio_knobs: $pass passed, $fail failed"
exit 0
