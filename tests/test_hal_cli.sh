#!/bin/sh
# isoterra — the hardware options end to end on a machine without the
# hardware: a missing gpiochip or video device is reported and rendering
# goes on (exit 0, the PNG written); a device of the wrong kind or a bad
# hardware setting is one clear error and exit 2.
BIN=${1:-${ISOTERRA_BIN:-./build/isoterra}}
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
cd "$T" || exit 1
pass=0
fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*" >&2; }
run() { "$BIN" --size 64x48 --grid 8 --count 3 --out o.png "$@" >out 2>err; }

rm -f o.png
run --gpio-chip /nonexistent/gpiochip --enc1-a 0 --enc1-b 1 --button1-line 2
[ $? -eq 0 ] && [ -s o.png ] && ok || bad "missing gpiochip: not survived: $(cat err)"
grep -q "gpio: cannot open gpiochip '/nonexistent/gpiochip'" err && ok || bad "missing gpiochip not reported: $(cat err)"
[ "$(grep -c gpiochip err)" -eq 1 ] && ok || bad "missing gpiochip reported more than once: $(cat err)"

rm -f o.png
run --v4l2 /dev/video-nonexistent
[ $? -eq 0 ] && [ -s o.png ] && ok || bad "missing video device: not survived: $(cat err)"
grep -q "v4l2: /dev/video-nonexistent: cannot open" err && ok || bad "missing video device not reported: $(cat err)"

run --v4l2 /dev/null
[ $? -eq 2 ] && grep -q "not a V4L2 device" err && ok || bad "/dev/null as video device: rc/msg: $(cat err)"
run --enc1-a 3
[ $? -eq 2 ] && grep -q "enc1_a and enc1_b" err && ok || bad "half an encoder: $(cat err)"
run --v4l2-format MJPG
[ $? -eq 2 ] && grep -q "v4l2_format" err && ok || bad "bad format name: $(cat err)"
run --screenshot shot.jpg
[ $? -eq 2 ] && grep -q "screenshot" err && ok || bad "bad screenshot name: $(cat err)"
run --screenshot 'a%s.png'
[ $? -eq 2 ] && grep -q "screenshot: 'a%s.png' must end in .png with at most one %d" err && ok ||
	bad "a screenshot name that cannot number its files: $(cat err)"
run --enc1-steps-per-detent 3 --gpio-chip x --enc1-a 0 --enc1-b 1
[ $? -eq 2 ] && grep -q "1, 2 or 4" err && ok || bad "3 steps per detent: $(cat err)"
# a file that is not an evdev node (/dev/zero reads zeros forever): refused at
# start, not read until the end of time
timeout -k 5 60 "$BIN" --size 64x48 --grid 8 --count 3 --out o.png --keyboard evdev --keyboard-evdev /dev/zero >out 2>err
rc=$?
[ $rc -eq 2 ] && grep -q "/dev/zero is not an evdev input device" err && ok ||
	bad "/dev/zero as evdev keyboard: rc $rc (124 or 137: hung): $(cat err)"
# the screenshot key on a terminal (script(1) gives the program one): the
# screenshot sink writes the frame asked for to the first numbered name,
# and q ends the run
if command -v script >/dev/null; then
	rm -f shot-*.png o.png
	(sleep 2; printf 's'; sleep 2; printf 'q') | timeout -k 5 120 script -qec "'$BIN' --keyboard tty --size 64x48 \
		--grid 8 --count 1000000 --out o.png --screenshot 'shot-%d.png'" /dev/null >shot.log 2>&1
	rc=$?
	size=$(python3 -c "import struct,sys; d=open('shot-0.png','rb').read(24); \
		print('%dx%d' % struct.unpack('>II', d[16:24]) if d[:8] == b'\x89PNG\r\n\x1a\n' else 'not a PNG')" 2>/dev/null)
	[ $rc -eq 0 ] && [ "$size" = 64x48 ] && grep -q "screenshot: shot-0.png" shot.log && [ ! -e shot-1.png ] && ok ||
		bad "screenshot key: rc $rc, shot-0.png '$size': $(tr -d '\r' <shot.log | grep -v '^\[' | tail -3)"
	# the next-preset key in the world scene: the world is made again for
	# the new terrain (every block; before, only blocks the flight reached
	# later had it) and its flight starts again from the preset's spawn
	(sleep 3; printf 'n'; sleep 4; printf 'q') | timeout -k 5 120 script -qec "'$BIN' --keyboard tty --scene world \
		--preset canyon --size 64x48 --count 1000000 --out o.png" /dev/null >pre.log 2>&1
	rc=$?
	[ $rc -eq 0 ] && grep -q "knob: preset default" pre.log &&
		grep -qE "world: the terrain changed: [1-9][0-9]* blocks made again" pre.log && ok ||
		bad "next-preset key in the world: rc $rc: $(tr -d '\r' <pre.log | grep -v '^\[' | tail -3)"
else
	echo "SKIP screenshot and preset keys: no script(1)"
fi
echo "hal_cli: $pass passed, $fail failed"
[ $fail -eq 0 ]
