#!/bin/sh
# isoterra — EGL devices (--platform device): --list-devices lists every
# device eglQueryDevicesEXT gives, in its order, and exits 0; --device N
# (an index) or --device PATH (a DRM node, EGL_EXT_device_drm's device
# file or EGL_EXT_device_drm_render_node's render node) opens that one
# device, under --platform device or auto; $ISOTERRA_DEVICE is the default;
# a device that is not there (an index out of range, a path no device has),
# a malformed one or one given to another platform is refused with one
# line and a non-zero exit, before any file is written.
#
# What the machine has decides what can be opened: here Mesa's software
# device (EGL_MESA_device_software, no DRM node) and perhaps none with a
# DRM node; on a machine with GPUs every listed device that gives a
# context is opened by index and by each of its DRM nodes.
# shellcheck disable=SC2086 # $small is a word list
BIN=${1:-${ISOTERRA_BIN:-./build/isoterra}}
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
MAX_MSG_LINES=1
NO_OUTPUT=$T/x.png
. "$(dirname "$0")/cli_lib.sh"
export XDG_CACHE_HOME="$T/cache"
unset ISOTERRA_DEVICE
cd "$T" || exit 1
small="--size 64x48 --grid 8 --out $T/x.png"

# renders what args...: exit 0 and a picture
renders() {
	what=$1
	shift
	rm -f "$T/x.png"
	# shellcheck disable=SC2086 # $small is a word list
	if "$BIN" $small "$@" >run.txt 2>&1 && [ -s "$T/x.png" ]; then
		ok
	else
		bad "$what: isoterra $*: $(tail -3 run.txt)"
	fi
}

# ---- the list
if "$BIN" --list-devices >list.txt 2>list.err; then ok; else bad "--list-devices exited non-zero: $(cat list.err)"; fi
[ ! -s list.err ] && ok || bad "--list-devices wrote to stderr: $(cat list.err)"
cat list.txt
# "N: KIND, NODES" lines, numbered from 0 in order
n=$(grep -cE '^[0-9]+: (GPU|other|software), ' list.txt)
i=0
while [ $i -lt "$n" ]; do
	grep -qE "^$i: " list.txt || bad "device $i missing from the list"
	i=$((i + 1))
done
if [ "$n" -eq 0 ]; then
	grep -q '^no EGL device' list.txt && ok || bad "no device lines and no 'no EGL device' line"
else
	[ "$(grep -c '^   extensions: ' list.txt)" -eq "$n" ] && ok || bad "not one extensions line per device"
	grep -qE '^without --device, --platform device opens ([0-9]+|none)' list.txt && ok || bad "no default line"
fi
# --list-devices exits before anything else is checked or written
if "$BIN" --list-devices --size 1x1 --out "$T/x.png" >/dev/null 2>&1 && [ ! -e "$T/x.png" ]; then ok; else
	bad "--list-devices with other options did not just list"
fi
"$BIN" --help >help.txt 2>&1
grep -q -- '--device N|PATH' help.txt && grep -q -- '--list-devices' help.txt && grep -q '^  --device ' help.txt &&
	ok || bad "--help lacks --device / --list-devices"
if [ -n "${ISOTERRA_BUILD:-}" ] && [ -f "$ISOTERRA_BUILD/isoterra.1" ]; then
	grep -q 'list\\-devices' "$ISOTERRA_BUILD/isoterra.1" && grep -q '^\.B \\-\\-device' "$ISOTERRA_BUILD/isoterra.1" &&
		ok || bad "the manual page lacks --device / --list-devices"
fi

# ---- refusals: one line, non-zero, no file
expect_fail "^isoterra: error: --device $n: there (is one EGL device, 0|are $n EGL devices, 0\\.\\.$((n - 1))) \\(see --list-devices\\)$" \
	$small --platform device --device "$n"
expect_fail "^isoterra: error: --device 4096: there " $small --device 4096
expect_fail "^isoterra: error: --device /dev/dri/renderD4711: no EGL device has this DRM node: No such file or directory \\($n devices?; see --list-devices\\)$" \
	$small --platform device --device /dev/dri/renderD4711
# a file that exists but is no device's node
expect_fail "^isoterra: error: --device $T/list.txt: no EGL device has this DRM node \\(" $small --device "$T/list.txt"
expect_fail "^isoterra: error: device: 'gpu0' is neither an EGL device index \\(0, 1, \\.\\.\\.\\) nor a DRM node path" \
	$small --platform device --device gpu0
expect_fail "^isoterra: error: device: '-1' is neither" $small --device=-1
expect_fail "^isoterra: error: device: '1234567890' is neither" $small --device 1234567890
expect_fail "^isoterra: error: device: '0' names an EGL device of --platform device, not of 'surfaceless'$" \
	$small --platform surfaceless --device 0
expect_fail "^isoterra: error: device: '0' names an EGL device of --platform device, not of 'x11'" $small --platform x11 --device 0
# the environment's default is checked the same way, and named
ISOTERRA_DEVICE=4096 expect_fail "^isoterra: error: ISOTERRA_DEVICE 4096: there " $small --platform device
ISOTERRA_DEVICE=/dev/dri/renderD4711 expect_fail "^isoterra: error: ISOTERRA_DEVICE /dev/dri/renderD4711: no EGL device" \
	$small --platform device
# a config file's device goes through the same checks
printf 'device = gpu0\n' >bad.conf
expect_fail "^isoterra: error: device: 'gpu0' is neither" $small --config bad.conf

# ---- every device that gives a context opens by index, and by its DRM nodes
opened=0
i=0
while [ $i -lt "$n" ]; do
	block=$(awk -v i="$i" '$0 ~ "^[0-9]+: " { on = ($0 ~ "^" i ": ") } on' list.txt)
	if echo "$block" | grep -q '^   GL: '; then
		renderer=$(echo "$block" | sed -n 's/^   GL: \(.*\) | .*/\1/p')
		renders "device $i" --platform device --device "$i"
		# the verbose log names the device and its renderer
		# shellcheck disable=SC2086
		"$BIN" $small --platform device --device "$i" --verbose >v.txt 2>&1
		grep -qF "platform device on $renderer" v.txt && ok || bad "device $i: the log does not name '$renderer': $(grep 'platform ' v.txt)"
		renders "device $i under auto" --device "$i"
		ISOTERRA_DEVICE=$i renders "ISOTERRA_DEVICE=$i" --platform device
		for node in $(echo "$block" | head -1 | tr ',' '\n' | sed -n 's/^ *\(\/.*\)$/\1/p'); do
			renders "device $i as $node" --platform device --device "$node"
			"$BIN" $small --platform device --device "$node" --verbose >v.txt 2>&1
			grep -qF "platform device on $renderer" v.txt && ok || bad "$node: not device $i's renderer"
		done
		opened=$((opened + 1))
	else
		# a device that gives no context is refused with its reason, by index
		expect_fail "^isoterra: error: EGL device $i.* \\(--device $i\\): " $small --platform device --device "$i"
	fi
	i=$((i + 1))
done
echo "devices: $n listed, $opened give a context"

echo "devices: $pass passed, $fail failed"
[ $fail -eq 0 ]
