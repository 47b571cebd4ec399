#!/bin/sh
# isoterra — Wayland backend as a client of Weston's headless backend
# (pixman renderer): a fullscreen window presents frames (frame callbacks
# counted), Weston's screenshot of the output matches the headless render of
# the same frame, SIGTERM ends the app cleanly, --count N exits by itself,
# auto picks wayland, a missing compositor is one clear error.
. "$(dirname "$0")/lib.sh"
need weston weston-screenshooter
scratch # $T; kills $APID and $SERVER_PID on exit
ARGS="--grid 24 --cam-spin 0 --seed 7 --fps 1000 --water-octaves 0" # a still picture, so any frame on screen matches the reference: --fps 1000 all but stops the clock, and a flat mirror has no waves to move (a fast machine shows frame 300 or later, 0.3 s on, where moving waves differ)
OUT_W=320
OUT_H=240

XDG_RUNTIME_DIR=$T/xdg
mkdir -m 700 "$XDG_RUNTIME_DIR"
export XDG_RUNTIME_DIR
unset DISPLAY
SOCK=isoterra-test-$$
# --debug: lets weston-screenshooter take the screenshot.  No animations:
# the desktop shell's default fades the whole output in from black at
# start-up (and zooms a new window in), so a screenshot taken while the
# first frames arrive was darker by up to 9 levels (mean 3-4) whenever the
# program was quick to show them
cat >"$T/weston.ini" <<'INI'
[shell]
startup-animation=none
animation=none
focus-animation=none
INI
weston --backend=headless-backend.so --use-pixman --width=$OUT_W --height=$OUT_H --socket=$SOCK \
	--idle-time=0 --config="$T/weston.ini" --debug --log="$T/weston.log" >"$T/weston.out" 2>&1 &
SERVER_PID=$!
n=0
while [ ! -S "$XDG_RUNTIME_DIR/$SOCK" ] && alive "$SERVER_PID" && [ $n -lt 200 ]; do sleep 0.1; n=$((n + 1)); done
if [ ! -S "$XDG_RUNTIME_DIR/$SOCK" ]; then
	bad "weston did not start: $(tail -5 "$T/weston.log" "$T/weston.out")"
	echo "$pass passed, $fail failed"
	exit 1
fi
WAYLAND_DISPLAY=$SOCK
export WAYLAND_DISPLAY
t0=$(date +%s)

# 1. fullscreen: the window is the whole output; screenshot vs headless
"$BIN" --platform wayland --fullscreen --hide-cursor $ARGS --count 0 --fps-report 0.2 >"$T/app1.log" 2>&1 &
APID=$!
if wait_frames "$T/app1.log" 4 60 "$APID"; then
	ok "wayland: frames presented ($(presented "$T/app1.log") so far)"
	wait_size "$T/app1.log" ${OUT_W}x$OUT_H 60 "$APID" || bad "wayland: no frame at the output's size ${OUT_W}x$OUT_H"
	mkdir "$T/shot"
	(cd "$T/shot" && weston-screenshooter) >"$T/shot.log" 2>&1
	shot=$(ls "$T"/shot/*.png 2>/dev/null | head -1)
	if [ -n "$shot" ]; then
		headless "$T/ref.png" ${OUT_W}x$OUT_H $ARGS &&
			compare "weston screenshot (fullscreen ${OUT_W}x$OUT_H) vs headless" "$shot" "$T/ref.png" --max-mean 1
		# --max-mean 1: with the start-up fade off the grab is the frame
		# itself (mean 0.000 in six runs here); the screenshots a CI host
		# and this machine took during the fade were off everywhere by up
		# to 4-9 levels (mean 1.1-4.0), which a limit of 3 did not always
		# hold
	else
		bad "weston-screenshooter wrote no PNG: $(cat "$T/shot.log")"
	fi
else
	bad "wayland: no frames presented: $(cat "$T/app1.log")"
fi
stop "$APID"
APID=
[ "$RC" = 0 ] && ok "SIGTERM: exit 0" || bad "SIGTERM: exit $RC: $(tail -3 "$T/app1.log")"
line=$(grep -oE 'wayland: [0-9]+ frames presented, [0-9]+ shown' "$T/app1.log")
np=$(echo "$line" | awk '{print $2}')
ns=$(echo "$line" | awk '{print $5}')
if [ -n "$np" ] && [ "$np" -ge 4 ] && [ "$ns" -ge $((np - 2)) ]; then
	ok "frame callbacks: $line"
else
	bad "frame callbacks: '$line' (want >= 4 presented, shown >= presented - 2)"
fi

# 2. a window (not fullscreen), --count 5: exits by itself
if "$BIN" --platform wayland --size 160x120 $ARGS --count 5 --out "$T/app2.png" >"$T/app2.log" 2>&1; then
	line=$(grep -oE 'wayland: [0-9]+ frames presented, [0-9]+ shown' "$T/app2.log")
	ns=$(echo "$line" | awk '{print $5}')
	case "$line" in
	"wayland: 5 frames presented"*) [ "$ns" -ge 4 ] && ok "--count 5: $line" || bad "--count 5: $line (want >= 4 shown)" ;;
	*) bad "--count 5: '$line': $(tail -3 "$T/app2.log")" ;;
	esac
	headless "$T/ref160.png" 160x120 $ARGS --count 5 && compare "--out of a wayland run vs headless (frame 5)" "$T/app2.png" "$T/ref160.png" --max-mean 0 --max-frac 0
else
	bad "--count 5 run failed: $(cat "$T/app2.log")"
fi

# 3. auto picks wayland when WAYLAND_DISPLAY is set
"$BIN" --platform auto --size 96x64 --grid 8 --count 1 --out "$T/auto.png" --verbose >"$T/auto.log" 2>&1
grep -q "platform wayland" "$T/auto.log" && ok "auto with WAYLAND_DISPLAY -> wayland" || bad "auto did not pick wayland: $(grep -i platform "$T/auto.log" | head -3)"

# 4. no compositor: one clear error, non-zero exit
WAYLAND_DISPLAY=isoterra-nonexistent "$BIN" --platform wayland --size 96x64 --grid 8 >"$T/now.log" 2>&1
rc=$?
if [ $rc -ne 0 ] && grep -q "cannot connect to the Wayland compositor 'isoterra-nonexistent'" "$T/now.log" &&
	[ "$(grep -c . "$T/now.log")" -le 2 ]; then
	ok "no compositor: exit $rc, '$(cat "$T/now.log")'"
else
	bad "no compositor: exit $rc, $(cat "$T/now.log")"
fi
echo "wayland display test: $(($(date +%s) - t0)) s"
echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
