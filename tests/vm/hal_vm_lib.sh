# isoterra — shared helpers of the hardware-layer VM tests (tests/vm/gpio_*.sh,
# tests/vm/v4l2_*.sh): the Debian kernel under QEMU (TCG), a busybox
# initramfs with the virtio + 9p modules, the host's / as a read-only 9p
# root to chroot into (Mesa, libgpiod, v4l-utils, the build tree), a writable
# 9p results folder, and gpio-sim built out of tree from linux-source-6.1.
# See ../shared/vm/RECIPE.md.  Sourced; uses HALVM_CACHE (a cache folder in
# the build tree) and HERE (tests/vm: mkinitramfs.sh, hal_init).  Functions
# print one line why when they cannot run.

# Cannot run here: a skip (77) on a developer's machine, a failure where the
# suite must run them (tools/test-all.sh sets ISOTERRA_REQUIRE_DEVICE_TESTS,
# as for the display tests).
halvm_skip() {
	if [ "${ISOTERRA_REQUIRE_DEVICE_TESTS:-0}" = 1 ]; then
		echo "FAIL: $* (sh tools/deps.sh installs it)"
		exit 1
	fi
	echo "SKIP: $*"
	exit 77
}

# The newest installed kernel release with its modules and headers (never
# hard-coded; a machine may have several kernels in /boot).
halvm_release() {
	for r in $(ls /boot/vmlinuz-* 2>/dev/null | sed 's|.*/vmlinuz-||' | sort -rV); do
		[ -d "/lib/modules/$r/kernel" ] && [ -d "/lib/modules/$r/build" ] && { echo "$r"; return; }
	done
}

halvm_require() {
	command -v qemu-system-x86_64 >/dev/null || halvm_skip "qemu-system-x86_64 missing (sh tools/deps.sh)"
	[ -x /bin/busybox ] && /bin/busybox --list | grep -qx insmod || halvm_skip "busybox-static missing"
	HALVM_REL=$(halvm_release)
	[ -n "$HALVM_REL" ] || halvm_skip "no /boot/vmlinuz-* (apt-get install linux-image-amd64)"
	[ -r "/boot/vmlinuz-$HALVM_REL" ] || halvm_skip "/boot/vmlinuz-$HALVM_REL not readable"
	[ -d "/lib/modules/$HALVM_REL/kernel" ] || halvm_skip "no modules for $HALVM_REL"
	command -v cpio >/dev/null || halvm_skip "cpio missing"
	mkdir -p "$HALVM_CACHE" || halvm_skip "cannot create $HALVM_CACHE"
}

# gpio-sim as an out-of-tree module (Debian's 6.1 config has no GPIO_SIM).
# Sets HALVM_GPIOSIM to the .ko (halvm_gpio_sim_path: where it is cached;
# the folder's name changes with what the build changes in the source).
#
# One change to the simulator's teardown: Linux 6.1 frees the interrupt of
# a line that a program still monitors for edges when its chip goes away
# (gpio-sim disposes of its mappings, irq_free_desc() removes /proc/irq/N
# with the program's entry still in it: "removing non-empty directory");
# when the program then closes its request, free_irq() removes that entry
# from the freed folder and corrupts the kernel's slab, which faults later
# in some allocation (seen in CI: a general protection fault in
# __proc_create under request_threaded_irq, a line requested again after
# the chip came back; and once in a line request's kmalloc).  Later
# kernels release such interrupts from the character device first (6.7,
# "gpiolib: cdev: release IRQs when the gpio chip device is removed"); here
# the simulator keeps a mapping that still has a handler, and keeps its
# interrupt domain if any does (a leak of a few hundred bytes per removal
# in a test VM).  What the tests check, a chip vanishing under the app's
# requested lines, happens as before; the guest kernel survives it.
halvm_gpio_sim_path() { echo "$HALVM_CACHE/gpio-sim-$HALVM_REL-keepirq/gpio-sim-oot.ko"; }
halvm_gpio_sim() {
	HALVM_GPIOSIM=$(halvm_gpio_sim_path)
	d=${HALVM_GPIOSIM%/*}
	[ -s "$HALVM_GPIOSIM" ] && return 0
	[ -r /usr/src/linux-source-6.1.tar.xz ] || halvm_skip "linux-source-6.1 missing"
	[ -d "/lib/modules/$HALVM_REL/build" ] || halvm_skip "linux-headers-$HALVM_REL missing"
	rm -rf "$d.tmp" && mkdir -p "$d.tmp" || return 1
	tar -xaf /usr/src/linux-source-6.1.tar.xz -C "$d.tmp" --strip-components=1 --wildcards \
		'*/drivers/gpio/gpio-sim.c' '*/drivers/gpio/gpiolib.h' '*/kernel/irq/irq_sim.c' || return 1
	(
		cd "$d.tmp" || exit 1
		cp drivers/gpio/gpio-sim.c drivers/gpio/gpiolib.h kernel/irq/irq_sim.c . || exit 1
		# irq_to_desc() is not exported to modules; equivalent here:
		sed -i 's/handle_simple_irq(irq_to_desc(irqnum));/generic_handle_irq(irqnum);/' irq_sim.c
		# the teardown kept from freeing a monitored line's interrupt (above):
		# whether it has a handler is asked under the descriptor's request
		# mutex, which free_irq() holds until the handler's /proc entry is gone
		grep -q '^		irq_dispose_mapping(irq_find_mapping(chip->irq_sim, i));$' gpio-sim.c &&
			grep -q '^#include "gpiolib.h"$' gpio-sim.c && grep -q '^	irq_work_sync(&work_ctx->work);$' irq_sim.c ||
			{ echo "gpio-sim: the teardown to change is not in this source"; exit 1; }
		cat >keep.c <<'KEEP'

static void gpio_sim_dispose_unless_requested(unsigned int virq)
{
	struct irq_data *data = virq ? irq_get_irq_data(virq) : NULL;
	struct irq_desc *desc;
	bool requested;

	if (!data)
		return;
	desc = irq_data_to_desc(data);
	mutex_lock(&desc->request_mutex);
	requested = desc->action != NULL;
	mutex_unlock(&desc->request_mutex);
	if (!requested)
		irq_dispose_mapping(virq);
}
KEEP
		sed -i -e '/^#include "gpiolib.h"$/r keep.c' \
			-e 's/^\t\tirq_dispose_mapping(irq_find_mapping(chip->irq_sim, i));$/\t\tgpio_sim_dispose_unless_requested(irq_find_mapping(chip->irq_sim, i));/' gpio-sim.c
		sed -i 's/^\tirq_work_sync(&work_ctx->work);$/&\n\tfor (unsigned int hw = 0; hw < work_ctx->irq_count; hw++)\n\t\tif (irq_find_mapping(domain, hw)) {\n\t\t\tpr_warn("irq_sim: line %u still requested: its domain is kept\\n", hw);\n\t\t\treturn;\n\t\t}/' irq_sim.c
		printf 'obj-m := gpio-sim-oot.o\ngpio-sim-oot-objs := gpio-sim.o irq_sim.o\n' >Makefile
		make -s -C "/lib/modules/$HALVM_REL/build" M="$PWD" modules >build.log 2>&1 || { cat build.log; exit 1; }
	) || return 1
	mkdir -p "$d" && cp "$d.tmp/gpio-sim-oot.ko" "$HALVM_GPIOSIM" && rm -rf "$d.tmp"
}

# initramfs: busybox, virtio_pci + 9p modules and hal_init (mounts the host
# and runs "chroot /host /bin/sh $halvm_script" from the kernel command
# line), built by mkinitramfs.sh like the KMS test's; rebuilt when either
# script changes.
halvm_initramfs() {
	HALVM_INITRD="$HALVM_CACHE/initramfs-$HALVM_REL.cpio.gz"
	[ -s "$HALVM_INITRD" ] && [ "$HALVM_INITRD" -nt "$HERE/hal_init" ] && [ "$HALVM_INITRD" -nt "$HERE/mkinitramfs.sh" ] &&
		return 0
	sh "$HERE/mkinitramfs.sh" "$HALVM_INITRD" "$HALVM_REL" "$HERE/hal_init" virtio_pci 9pnet_virtio 9p >/dev/null
}

# Mesa's shader cache for the guest, kept between runs: software rendering
# in the guest compiles every shader anew otherwise (a minute or more under
# TCG).  The guest's CPU (-cpu max) differs from the host's, so it has its
# own folder: the one every VM test of this kernel shares (test_kms.sh's
# too: the same Mesa on the same virtual CPU compiles the same programs
# alike, so a VM test after another finds the extraction's and the
# renderer's programs compiled).  Mesa's cache mmaps its index, which a 9p mount does not serve
# well, so the guest copies the folder into its tmpfs at the start
# (halvm_env's MESA_SHADER_CACHE_DIR) and back at the end (save_cache).
# Sets HALVM_MESA_CACHE ("" when it cannot be created: no cache).
halvm_mesa_cache() {
	HALVM_MESA_CACHE=${ISOTERRA_VM_CACHE:-${XDG_CACHE_HOME:-${HOME:-/tmp}/.cache}/isoterra/vm-mesa-$HALVM_REL}
	mkdir -p "$HALVM_MESA_CACHE" 2>/dev/null || HALVM_MESA_CACHE=
}

# halvm_env RESULTS_DIR: the guest's environment (sourced by the guest
# scripts): the shader cache and save_cache, quiet EGL.
halvm_env() {
	cat >>"$1/env.sh" <<'ENV'
export EGL_LOG_LEVEL=fatal
save_cache() { :; }
if mountpoint -q /run/mesa-cache 2>/dev/null; then
	mkdir -p /run/mesa-local && cp -a /run/mesa-cache/. /run/mesa-local/ &&
		export MESA_SHADER_CACHE_DIR=/run/mesa-local
	save_cache() { cp -a /run/mesa-local/. /run/mesa-cache/ 2>/dev/null; }
fi
ENV
}

# halvm_boot RESULTS_DIR GUEST_SCRIPT TIMEOUT_S: boots, runs the script in
# the chroot (it sees RESULTS_DIR as /run/res), console to RESULTS_DIR/console.log.
halvm_boot() {
	res=$1 script=$2 tmo=$3 extra=
	shift 3
	set --
	if [ -n "$HALVM_MESA_CACHE" ]; then
		extra=halvm_cache=1
		set -- -virtfs "local,path=$HALVM_MESA_CACHE,mount_tag=cache,security_model=none,multidevs=remap"
	fi
	timeout "$tmo" qemu-system-x86_64 -cpu max -m 2048 -smp 2 -nographic -no-reboot \
		-kernel "/boot/vmlinuz-$HALVM_REL" -initrd "$HALVM_INITRD" \
		-append "console=ttyS0 panic=-1 oops=panic loglevel=3 halvm_script=$script $extra" \
		-virtfs local,path=/,mount_tag=host,security_model=none,readonly=on,multidevs=remap \
		-virtfs "local,path=$res,mount_tag=res,security_model=none,multidevs=remap" "$@" \
		</dev/null >"$res/console.log" 2>&1
	rc=$?
	[ $rc -eq 124 ] && echo "VM timed out after $tmo s"
	return $rc
}

# halvm_oops RESULTS_DIR: the guest kernel's oops, if its console shows one
# (its first line and the call trace's first frames; status 0), else
# status 1.  The boot passes oops=panic: a kernel fault ends the VM at
# once instead of leaving a guest that hangs until the timeout.
halvm_oops() {
	grep -qE '(general protection fault|BUG: |Oops: |kernel BUG at)' "$1/console.log" 2>/dev/null || return 1
	grep -E -m1 '(general protection fault|BUG: |Oops: |kernel BUG at)' "$1/console.log" | tr -d '\r'
	grep -A6 -m1 'Call Trace:' "$1/console.log" | tail -6 | tr -d '\r'
	return 0
}

# halvm_cores RESULTS_DIR BINARY [ROOT]: the backtrace of each core the
# guest left (core_pattern /run/res/core.%e.%p); the guest runs the host's
# files, so the host's gdb reads them with the same binary and libraries
# (those under ROOT when the app ran in a chroot of ROOT).
halvm_cores() {
	for c in "$1"/core.*; do
		[ -f "$c" ] || continue
		echo "--- core dump $c:"
		if command -v gdb >/dev/null; then
			gdb -q -batch ${3:+-ex "set sysroot $3"} -ex "thread apply all bt 12" "${3:-}$2" "$c" 2>&1 | tail -80
		else
			echo "(no gdb here to read it)"
		fi
	done
}
