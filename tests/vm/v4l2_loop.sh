#!/bin/sh
# isoterra — V4L2 output against the real kernel: Debian's kernel under
# QEMU, vivid with a capture and an output node (node_types=0x101), both on
# their HDMI connector with the output's DV timing (1280x720), "Loop Video"
# on and vivid's text overlay off.  isoterra renders headless in the guest and
# renders frames a quarter of that (software rendering in the guest is
# slow) and streams every one to the output node (--v4l2, YUYV, BT.601
# limited, GPU conversion); vivid scales them 4x onto the HDMI timing, so on
# the capture side 4x4 blocks are averaged back down for the comparison; the frames that come back on the capture node must match the
# app's own rendered frame (its PNG of the same frame): the capture is
# converted back to RGB on the CPU (hal_probe compare) and the PSNR must
# reach MIN_PSNR.  Negative control: a capture taken before the app streams
# (vivid's test pattern) must not match.  Also: the capture node given as
# --v4l2 is refused with one clear message (exit 2), and an output node
# another program streams to is reported busy while the frames are rendered;
# the output node disappearing
# while the app streams (vivid's Disconnect control) is reported, rendering
# goes on, and the stream resumes when the node is back (a second capture
# matches again); the driver unloaded (rmmod vivid) leaves no node to open
# (reported once), and the stream resumes after it is loaded again.
# usage: v4l2_loop.sh ISOTERRA HAL_PROBE BUILD_DIR [sanitize]
BIN=$1
PROBE=$2
BUILD=$3
# vivid scales the 4x smaller frames up with its own scaler and YUYV halves
# the chroma: the looped frame measured 39.5 dB against the app's frame,
# vivid's test pattern 9.2-9.4 dB.  (With the earlier conversion shader,
# which sampled the frame through texture() with filtering, the guest's
# llvmpipe gave 21.6 dB, mean error 10 levels: exact on the host, not in the
# guest.  The threshold sits well above that and below the measurement.)
MIN_PSNR=30
[ "${4:-none}" = none ] || { echo "SKIP: VM tests run in the plain build only (this one: $4)"; exit 77; }
HERE=$(cd "$(dirname "$0")" && pwd)
HALVM_CACHE="$BUILD/hal-vm-cache"
. "$HERE/hal_vm_lib.sh"
halvm_require
halvm_initramfs || { echo "FAIL: building the initramfs failed"; exit 1; }
halvm_mesa_cache
RES=$(mktemp -d "$BUILD/hal-vm-v4l2.XXXXXX")
[ -n "$ISOTERRA_KEEP" ] && echo "results kept in $RES" || trap 'rm -rf "$RES"' EXIT
cat >"$RES/env.sh" <<ENV
BIN=$BIN
ENV
halvm_env "$RES"
t0=$(date +%s)
halvm_boot "$RES" "$HERE/v4l2_loop_guest.sh" "${ISOTERRA_VM_TIMEOUT:-760}"
echo "VM: $(($(date +%s) - t0)) s (kernel $HALVM_REL, TCG, shader cache ${HALVM_MESA_CACHE:-none})"
grep -aE "^(ok|FAIL|guest)" "$RES/console.log" | tr -d '\r'
fails=$(grep -ac '^FAIL' "$RES/console.log")
passes=$(grep -ac '^ok' "$RES/console.log")
if ! grep -aq "HALVM-EXIT 0" "$RES/console.log"; then
	echo "FAIL: the guest part failed; console:"
	tail -40 "$RES/console.log"
	[ -f "$RES/app.log" ] && { echo "--- app log:"; tail -20 "$RES/app.log"; }
	exit 1
fi
REF=$(cat "$RES/ref.name")
# expect CAPTURE match|differ WHAT: a capture against the app's frame $REF
expect() {
	if "$PROBE" compare "$RES/$1" "$RES/$REF" YUYV bt601 $MIN_PSNR $(cat "$RES/size"); then got=match; else got=differ; fi
	if [ $got = "$2" ]; then
		echo "ok $3 vs the app's frame $REF: $got (threshold $MIN_PSNR dB)"
		passes=$((passes + 1))
	else
		echo "FAIL $3 vs the app's frame $REF: $got, want $2 (threshold $MIN_PSNR dB)"
		fails=$((fails + 1))
	fi
}
expect cap.yuv match "the looped frames"
expect cap2.yuv match "the looped frames after the reconnection"
expect before.yuv differ "negative control, vivid's test pattern"
echo "v4l2_loop: $passes passed, $fails failed"
[ "$fails" -eq 0 ]
