#!/bin/sh
# isoterra — X11 backend in Xvfb: the window's content (xwd) matches the
# headless render of the same frame; resize (ConfigureNotify) re-renders at
# the new size; WM_DELETE_WINDOW and SIGTERM end the app cleanly (exit 0);
# --fullscreen fills the screen; --count N exits by itself; --rotate 90
# turns the picture in the window; paused, the app idles (CPU time); the
# governed world's results say the quality it held; a missing X server is
# one clear error; frames reach the window through MIT-SHM (a software
# renderer) or eglSwapBuffers, the same picture, and a server without
# MIT-SHM gets the swap.
. "$(dirname "$0")/lib.sh"
need Xvfb xwd "${X11POKE:-x11poke}"
scratch # $T; kills $APID and $SERVER_PID on exit
# static frames: the camera does not orbit, the field does not scroll
ARGS="--grid 24 --cam-spin 0 --seed 7 --fps 1000 --water-octaves 0" # a still picture, so any frame on screen matches the reference: --fps 1000 all but stops the clock, and a flat mirror has no waves to move (a fast machine shows frame 300 or later, 0.3 s on, where moving waves differ)
SCREEN=400x300

# Xvfb picks a free display number itself (-displayfd): no clash with
# other X servers on the machine.
Xvfb -displayfd 3 -nolisten tcp -screen 0 ${SCREEN}x24 3>"$T/display" >"$T/xvfb.log" 2>&1 &
SERVER_PID=$!
wait_for "$T/display" '^[0-9]+$' 20 "$SERVER_PID" || { bad "Xvfb did not start: $(cat "$T/xvfb.log")"; echo "$pass passed, $fail failed"; exit 1; }
DISPLAY=:$(cat "$T/display")
export DISPLAY
unset WAYLAND_DISPLAY
echo "Xvfb on $DISPLAY"

t0=$(date +%s)
# 1. a 240x160 window, kept running; grab it, resize it, close it
"$BIN" --platform x11 --size 240x160 $ARGS --count 0 --fps-report 0.2 --hide-cursor >"$T/app1.log" 2>&1 &
APID=$!
if wait_frames "$T/app1.log" 3 60 "$APID"; then
	ok "x11: window presents frames ($(presented "$T/app1.log") so far)"
	xwd -display "$DISPLAY" -name isoterra -out "$T/win.xwd" 2>"$T/xwd.log" || bad "xwd: $(cat "$T/xwd.log")"
	headless "$T/ref240.png" 240x160 $ARGS && compare "x11 window 240x160 vs headless" "$T/win.xwd" "$T/ref240.png"
	# the comparison can fail: another seed must not match
	headless "$T/other.png" 240x160 --grid 24 --cam-spin 0 --seed 8 &&
		if "$IMGCMP" "$T/win.xwd" "$T/other.png" >"$T/neg.txt" 2>&1; then
			bad "negative control: a different terrain matched: $(cat "$T/neg.txt")"
		else
			ok "negative control (seed 8) differs: $(cat "$T/neg.txt")"
		fi
	# resize: the app follows ConfigureNotify with a new render target
	"$X11POKE" resize isoterra 320 200 || bad "x11poke resize failed"
	# frames counted from the first report at the new size: a count taken
	# before the resize includes frames the old window showed (one CI run
	# grabbed such a frame, mean difference 45)
	if wait_for "$T/app1.log" '320x200 x11' 30 "$APID" && n1=$(presented "$T/app1.log") &&
		wait_frames "$T/app1.log" $((n1 + 6)) 30 "$APID"; then
		xwd -display "$DISPLAY" -name isoterra -out "$T/win320.xwd" 2>"$T/xwd.log" || bad "xwd: $(cat "$T/xwd.log")"
		headless "$T/ref320.png" 320x200 $ARGS && compare "x11 window resized to 320x200 vs headless" "$T/win320.xwd" "$T/ref320.png"
	else
		bad "x11: no frames at 320x200 after the resize: $(tail -3 "$T/app1.log")"
	fi
	# close button
	"$X11POKE" close isoterra || bad "x11poke close failed"
	if wait_for "$T/app1.log" 'x11: window closed' 20 "$APID"; then
		wait "$APID"
		rc=$?
		APID=
		[ $rc -eq 0 ] && ok "WM_DELETE_WINDOW: exit 0" || bad "WM_DELETE_WINDOW: exit $rc: $(tail -3 "$T/app1.log")"
		grep -Eq 'x11: [0-9]+ frames presented' "$T/app1.log" && ok "final frame count logged" || bad "no final frame count: $(tail -3 "$T/app1.log")"
	else
		bad "x11: WM_DELETE_WINDOW did not close the app: $(tail -3 "$T/app1.log")"
	fi
else
	bad "x11: no frames presented: $(cat "$T/app1.log")"
fi
[ -n "$APID" ] && { kill -KILL "$APID" 2>/dev/null; wait "$APID" 2>/dev/null; APID=; }

# 2. --fullscreen with no window manager: the window is the whole screen;
#    SIGTERM ends it cleanly; SIGUSR1 prints the frame rate
"$BIN" --platform x11 --fullscreen $ARGS --count 0 >"$T/app2.log" 2>&1 &
APID=$!
# SIGUSR1's default action ends a process: send it once the handler is in
wait_caught "$APID" 10 120 || bad "x11: no SIGUSR1 handler after 120 s: $(cat "$T/app2.log")"
n=0
while [ $n -lt 300 ] && ! grep -q 'fps' "$T/app2.log"; do kill -USR1 "$APID" 2>/dev/null; sleep 0.2; n=$((n + 1)); done
if grep -Eq 'fps [0-9.]+ .*[0-9]+ presented' "$T/app2.log"; then
	ok "SIGUSR1: $(grep -m1 fps "$T/app2.log")"
	wait_frames "$T/app2.log" 2 30 "$APID" || true
	xwd -display "$DISPLAY" -name isoterra -out "$T/full.xwd" 2>"$T/xwd.log" || bad "xwd: $(cat "$T/xwd.log")"
	headless "$T/ref400.png" $SCREEN $ARGS && compare "x11 --fullscreen ($SCREEN) vs headless" "$T/full.xwd" "$T/ref400.png"
else
	bad "SIGUSR1 gave no frame rate line: $(cat "$T/app2.log")"
fi
stop "$APID"
APID=
[ "$RC" = 0 ] && ok "SIGTERM: exit 0" || bad "SIGTERM: exit $RC: $(tail -3 "$T/app2.log")"
grep -q 'Terminated: stopping' "$T/app2.log" && ok "SIGTERM noticed by the loop" || bad "SIGTERM not logged: $(tail -3 "$T/app2.log")"

# 3. --count N: exits by itself after N frames, writes --out like headless
if "$BIN" --platform x11 --size 160x120 $ARGS --count 3 --out "$T/app3.png" >"$T/app3.log" 2>&1; then
	grep -q 'x11: 3 frames presented, 3 shown' "$T/app3.log" && ok "--count 3: 3 frames presented" || bad "--count 3: $(cat "$T/app3.log")"
	headless "$T/ref160.png" 160x120 $ARGS --count 3 && compare "--out of an x11 run vs headless (frame 3)" "$T/app3.png" "$T/ref160.png" --max-mean 0 --max-frac 0
else
	bad "--count 3 run failed: $(cat "$T/app3.log")"
fi

# 3b. a rotated panel (--rotate 90): the window shows the upright picture
# turned clockwise (the display's own pass, shaders/rotate.frag), the same
# as the headless render's file
"$BIN" --platform x11 --size 120x160 --rotate 90 $ARGS --count 0 --fps-report 0.2 >"$T/app4.log" 2>&1 &
APID=$!
if wait_frames "$T/app4.log" 2 60 "$APID"; then
	xwd -display "$DISPLAY" -name isoterra -out "$T/rot.xwd" 2>"$T/xwd.log" || bad "xwd: $(cat "$T/xwd.log")"
	headless "$T/ref-rot.png" 120x160 --rotate 90 $ARGS && compare "x11 --rotate 90 window vs headless" "$T/rot.xwd" "$T/ref-rot.png"
	headless "$T/ref-up.png" 160x120 $ARGS && compare "x11 --rotate 90 window turned back vs the upright render" "$T/ref-up.png" "$T/rot.xwd" --unturn 90
else
	bad "--rotate 90 window: no frames: $(cat "$T/app4.log")"
fi
stop "$APID"
APID=

# 3c. paused, the window idles: nothing is rendered until an input comes
#     (keys from a terminal: script's pty; p pauses and resumes, q quits),
#     once a second the picture shown is handed to the display again.  The
#     app's CPU time (utime + stime) over 3 s paused against 3 s running,
#     and the frames presented meanwhile.
# the app's pid: its command line in /proc (not script's shell, which
# holds the same words after "sh -c")
find_app() {
	for d in /proc/[0-9]*; do
		c=$(tr '\0' ' ' 2>/dev/null <"$d/cmdline")
		case $c in "$BIN --platform x11 --size 168x126 "*) echo "${d#/proc/}"; return ;; esac
	done
}
cputime() { awk -v hz="$(getconf CLK_TCK)" '{ printf "%.3f\n", ($14 + $15) / hz }' "/proc/$1/stat" 2>/dev/null; }
now() { date +%s.%N; }
mkfifo "$T/keys"
script -qec "'$BIN' --platform x11 --size 168x126 $ARGS --count 0 --fps-report 0.2 --keyboard tty" /dev/null \
	<"$T/keys" >"$T/app5.log" 2>&1 &
SPID=$!
exec 4>"$T/keys"
PPID5=
n=0
while [ -z "$PPID5" ] && [ $n -lt 100 ]; do
	PPID5=$(find_app)
	[ -n "$PPID5" ] || sleep 0.1
	n=$((n + 1))
done
if [ -n "$PPID5" ] && wait_frames "$T/app5.log" 3 60 "$PPID5"; then
	c0=$(cputime "$PPID5") s0=$(now) f0=$(presented "$T/app5.log")
	sleep 3
	c1=$(cputime "$PPID5") s1=$(now) f1=$(presented "$T/app5.log")
	printf p >&4
	if wait_for "$T/app5.log" 'knob: paused' 20 "$PPID5"; then
		sleep 1.5 # the paused picture shown, then idle
		c2=$(cputime "$PPID5") s2=$(now) f2=$(presented "$T/app5.log")
		sleep 3
		c3=$(cputime "$PPID5") s3=$(now) f3=$(presented "$T/app5.log")
		verdict=$(awk -v c0="$c0" -v c1="$c1" -v s0="$s0" -v s1="$s1" -v c2="$c2" -v c3="$c3" -v s2="$s2" \
			-v s3="$s3" -v f0="$f0" -v f1="$f1" -v f2="$f2" -v f3="$f3" 'BEGIN {
			run = (c1 - c0) / (s1 - s0); idle = (c3 - c2) / (s3 - s2)
			printf "running %.1f%% CPU, %d frames in %.1f s; paused %.1f%% CPU, %d frames in %.1f s",
				100 * run, f1 - f0, s1 - s0, 100 * idle, f3 - f2, s3 - s2
			exit !(run > 0.2 && idle < 0.25 * run && f3 - f2 <= 5 && f1 - f0 > f3 - f2) }')
		[ $? -eq 0 ] && ok "paused: idles ($verdict)" ||
			bad "paused: not idle ($verdict; want running above 20% CPU, paused under a quarter of it, at most 5 frames in 3 s)"
		printf p >&4
		if wait_for "$T/app5.log" 'knob: running' 20 "$PPID5" && wait_frames "$T/app5.log" $((f3 + 4)) 30 "$PPID5"; then
			ok "resumed: frames again ($f3 -> $(presented "$T/app5.log"))"
		else
			bad "resumed: no frames after the second p: $(tail -3 "$T/app5.log")"
		fi
	else
		bad "p on the terminal: not paused: $(tail -3 "$T/app5.log")"
	fi
	printf q >&4
	wait_for "$T/app5.log" 'x11: [0-9]+ frames presented' 20 "$PPID5" && ok "q on the terminal: the app ends" ||
		bad "q on the terminal: the app did not end: $(tail -3 "$T/app5.log")"
else
	bad "paused run: no frames: $(cat "$T/app5.log")"
fi
exec 4>&-
[ -n "$PPID5" ] && kill "$PPID5" 2>/dev/null
wait "$SPID" 2>/dev/null

# 3d. the governed world in a window: the results file says what quality the
#     governor held on average beside the frame times (--results "held"),
#     the same as the run's report line; an offline run says null
if "$BIN" --platform x11 --scene world --size 160x120 --count 40 --target-fps 30 --results "$T/gov.json" \
	>"$T/app6.log" 2>&1; then
	line=$(grep -o 'governor held render scale [0-9.]*, view distance x[0-9.]*, near LOD x[0-9.]*' "$T/app6.log")
	verdict=$(python3 - "$T/gov.json" "$line" <<'PY'
import json, sys
h = json.load(open(sys.argv[1]))["held"]
w = sys.argv[2].replace(",", "").split()
ok = (h is not None and 0.5 <= h["render_scale"] <= 1 and 0.55 <= h["view_distance"] <= 1 and
      0.6 <= h["near_lod"] <= 1 and 0 <= h["level_at_end"] <= 18 and len(w) == 11 and
      "%.2f" % h["render_scale"] == w[4] and "x%.2f" % h["view_distance"] == w[7] and
      "x%.2f" % h["near_lod"] == w[10])
print("held %s; the report: %s" % (h, sys.argv[2]))
sys.exit(0 if ok else 1)
PY
)
	[ $? -eq 0 ] && ok "governed window: $verdict" || bad "governed window: results and report disagree: $verdict"
else
	bad "governed world in a window failed: $(tail -3 "$T/app6.log")"
fi
"$BIN" --platform surfaceless --scene world --size 96x64 --count 2 --out "$T/w.png" --results "$T/off.json" >/dev/null 2>&1 &&
	python3 -c 'import json, sys; sys.exit(json.load(open(sys.argv[1]))["held"] is not None)' "$T/off.json" &&
	ok "an offline world: no governor, \"held\": null" || bad "an offline world's results: $(cat "$T/off.json")"

# 4. auto picks x11 when DISPLAY is set
"$BIN" --platform auto --size 96x64 --grid 8 --count 1 --out "$T/auto.png" --verbose >"$T/auto.log" 2>&1
grep -q "platform x11" "$T/auto.log" && ok "auto with DISPLAY -> x11" || bad "auto did not pick x11: $(grep -i platform "$T/auto.log" | head -3)"

# 5. no X server: one clear error, non-zero exit
DISPLAY=:4097 "$BIN" --platform x11 --size 96x64 --grid 8 >"$T/nox.log" 2>&1
rc=$?
if [ $rc -ne 0 ] && grep -q "cannot connect to the X server ':4097'" "$T/nox.log" && [ "$(grep -c . "$T/nox.log")" -le 2 ]; then
	ok "no X server: exit $rc, '$(cat "$T/nox.log")'"
else
	bad "no X server: exit $rc, $(cat "$T/nox.log")"
fi
# 6. how frames reach the window (--x11-present).  A software renderer on
#    a server with MIT-SHM: auto reads each frame back into memory it
#    shares with the X server and puts it from there (the windows above);
#    swap is eglSwapBuffers, the same picture.  A server without MIT-SHM:
#    auto swaps, the same picture; shm is one clear error.
if grep -q 'x11: frames put through MIT-SHM (a software renderer' "$T/app1.log"; then
	ok "auto, a software renderer: frames put through MIT-SHM (the windows compared above)"
elif grep -q 'x11: frames presented with eglSwapBuffers' "$T/app1.log"; then
	echo "skip: MIT-SHM: the renderer is not a software one here, auto swaps: $(grep -m1 eglSwapBuffers "$T/app1.log")"
else
	bad "auto: no line says how frames reach the window: $(head -3 "$T/app1.log")"
fi
# window W REF LOG ARGS...: a 240x160 window of this run matches the
# headless REF (the app stopped after); its log in LOG
window() {
	_what=$1 _ref=$2 _log=$3
	shift 3
	"$BIN" --platform x11 --size 240x160 $ARGS --count 0 --fps-report 0.2 "$@" >"$_log" 2>&1 &
	APID=$!
	if wait_frames "$_log" 3 60 "$APID"; then
		xwd -display "$DISPLAY" -name isoterra -out "$T/w.xwd" 2>"$T/xwd.log" || bad "xwd: $(cat "$T/xwd.log")"
		compare "$_what" "$T/w.xwd" "$_ref"
	else
		bad "$_what: no frames: $(cat "$_log")"
	fi
	stop "$APID"
	APID=
}
headless "$T/ref-p.png" 240x160 $ARGS
window "x11 --x11-present swap vs headless" "$T/ref-p.png" "$T/swap.log" --x11-present swap
grep -q 'x11: frames presented with eglSwapBuffers (--x11-present swap)' "$T/swap.log" &&
	ok "--x11-present swap: eglSwapBuffers" || bad "--x11-present swap: $(head -3 "$T/swap.log")"
# a GL that cannot read a frame back as BGRA (Mesa's extension override
# takes GL_EXT_read_format_bgra away): auto gives the pbuffer's context up
# and swaps on the window's config, the same picture
MESA_EXTENSION_OVERRIDE=-GL_EXT_read_format_bgra window "x11 without a BGRA read-back (auto) vs headless" \
	"$T/ref-p.png" "$T/nobgra.log"
if grep -q 'x11: frames put through MIT-SHM' "$T/nobgra.log"; then
	echo "skip: this GL ignores MESA_EXTENSION_OVERRIDE (not Mesa): the fallback from a pbuffer is not exercised"
elif grep -q 'eglSwapBuffers (the GL cannot read a frame back as BGRA' "$T/nobgra.log"; then
	ok "no BGRA read-back: auto swaps"
else
	bad "no BGRA read-back: $(head -3 "$T/nobgra.log")"
fi
kill -TERM "$SERVER_PID" 2>/dev/null
wait "$SERVER_PID" 2>/dev/null
Xvfb -displayfd 3 -nolisten tcp -extension MIT-SHM -screen 0 ${SCREEN}x24 3>"$T/display2" >"$T/xvfb2.log" 2>&1 &
SERVER_PID=$!
if wait_for "$T/display2" '^[0-9]+$' 20 "$SERVER_PID"; then
	DISPLAY=:$(cat "$T/display2")
	window "x11 without MIT-SHM (auto) vs headless" "$T/ref-p.png" "$T/noshm.log"
	if grep -q 'x11: frames presented with eglSwapBuffers (the X server has no MIT-SHM)' "$T/noshm.log"; then
		ok "a server without MIT-SHM: auto swaps ($(grep -m1 -o 'x11: frames presented.*' "$T/noshm.log"))"
	else
		bad "a server without MIT-SHM: auto does not say it swaps for that reason: $(head -3 "$T/noshm.log")"
	fi
	"$BIN" --platform x11 --size 96x64 --grid 8 --count 1 --out "$T/shm.png" --x11-present shm >"$T/shm.log" 2>&1
	rc=$?
	if [ $rc -ne 0 ] && grep -q -- "--x11-present shm: the X server has no MIT-SHM" "$T/shm.log" &&
		[ "$(grep -c . "$T/shm.log")" -le 2 ] && [ ! -e "$T/shm.png" ]; then
		ok "--x11-present shm without MIT-SHM: exit $rc, '$(cat "$T/shm.log")', no picture written"
	else
		bad "--x11-present shm without MIT-SHM: exit $rc, $(cat "$T/shm.log")"
	fi
else
	bad "Xvfb without MIT-SHM did not start: $(cat "$T/xvfb2.log")"
fi
echo "x11 display test: $(($(date +%s) - t0)) s"
echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
