#!/bin/sh
# isoterra — runs inside the test VM (chroot of the host's root over 9p,
# real Linux kernel, virtio-gpu KMS).  $1 is the results folder, shared with
# the host; config.sh there says what to run.  Each "shot NAME" asks the
# host for a QEMU screendump (req-NAME) and waits for it (ack-NAME).
R=$1
. "$R/config.sh"
export HOME="$R" TMPDIR="$R" EGL_LOG_LEVEL=fatal
# Mesa's shader cache lives in a host folder kept between runs (compiling
# the shaders is most of the time in the guest); without one, no cache.
if [ -n "${CACHE:-}" ]; then
	export MESA_SHADER_CACHE_DIR="$CACHE"
else
	export MESA_SHADER_CACHE_DISABLE=true
fi
say() { echo "guest: $*"; }
up() { cut -d' ' -f1 /proc/uptime; }
shot() {
	: >"$R/req-$1"
	n=0
	while [ ! -e "$R/ack-$1" ] && [ $n -lt 600 ]; do sleep 0.1; n=$((n + 1)); done
	[ -e "$R/ack-$1" ] || say "no screendump $1 from the host"
}
# stop_app SIGNAL NAME: the app ($pid) sent SIGNAL (TERM, or KILL when it
# showed nothing), waited for; its exit status in NAME.rc
stop_app() {
	kill -"$1" $pid 2>/dev/null
	wait $pid
	echo $? >"$R/$2.rc"
}
# state NAME: the KMS state (debugfs) of card0
state() { cat /sys/kernel/debug/dri/0/state >"$R/state-$1.txt" 2>&1; }
# wait for a line matching $2 in file $1 (timeout $3 s) while pid $4 lives
wait_line() {
	n=0
	while [ $n -lt $(($3 * 10)) ]; do
		grep -Eq "$2" "$1" 2>/dev/null && return 0
		kill -0 "$4" 2>/dev/null || { grep -Eq "$2" "$1" 2>/dev/null; return $?; }
		sleep 0.1
		n=$((n + 1))
	done
	return 1
}

n=0
while [ ! -e /dev/dri/card0 ] && [ $n -lt 100 ]; do sleep 0.1; n=$((n + 1)); done
[ -e /dev/dri/card0 ] || { say "no /dev/dri/card0"; ls -l /dev/dri; exit 1; }
say "card0 at $(up) s; modes: $(cat /sys/class/drm/card0-*/modes 2>/dev/null | tr '\n' ' ')"
state console
shot console

# 1. isoterra on KMS (atomic), kept running: screendump, then SIGTERM with
#    a second open file on the card (fd 3, opened once isoterra is the DRM
#    master), so the kernel's own last-close restore of the console cannot
#    hide a missing restore in the app
t=$(up)
"$BIN" --platform gbm $ARGS --count 0 --fps-report 0.01 >"$R/app.log" 2>&1 &
pid=$!
if wait_line "$R/app.log" ' [2-9] presented|[0-9][0-9]+ presented' 400 $pid; then
	say "isoterra (atomic): 2 frames after $(awk "BEGIN { print $(up) - $t }") s"
	exec 3<>/dev/dri/card0
	shot app
	state app
	stop_app TERM app
	state after
	shot after
else
	say "isoterra presented no frames"
	stop_app KILL app
	exec 3<>/dev/dri/card0
fi

# 1b. a rotated panel, --rotate 180 (90 in the hotplug run of 5, 270 in
#     the mirror of 4b): its scanout, then SIGTERM; the info line says who
#     turns it (the plane's rotation property where the driver offers the
#     turn, else the final pass)
"$BIN" --platform gbm $ARGS --rotate 180 --count 0 --fps-report 0.01 >"$R/rot180.log" 2>&1 &
pid=$!
if wait_line "$R/rot180.log" ' [2-9] presented|[0-9][0-9]+ presented' 300 $pid; then
	shot rot180
	stop_app TERM rot180
else
	say "isoterra --rotate 180 presented no frames"
	stop_app KILL rot180
fi

# 2. legacy modesetting, --count 3: exits by itself and restores; with
#    --platform auto (no DISPLAY, no WAYLAND_DISPLAY): auto must pick gbm
t=$(up)
timeout 300 "$BIN" --platform auto $ARGS --count 3 --kms-legacy --out "$R/legacy.png" >"$R/legacy.log" 2>&1
echo $? >"$R/legacy.rc"
state legacy
say "isoterra (legacy, 3 frames) rc $(cat "$R/legacy.rc") in $(awk "BEGIN { print $(up) - $t }") s"

# 3. kmscube (a sanity peer) does not restore the CRTC: with fd 3 still
#    open the console stays off -- the negative control of the checks above
t=$(up)
timeout 120 kmscube -D /dev/dri/card0 -c 4 >"$R/kmscube.log" 2>&1
echo $? >"$R/kmscube.rc"
state kmscube
shot kmscube
say "kmscube rc $(cat "$R/kmscube.rc") in $(awk "BEGIN { print $(up) - $t }") s"
exec 3>&-

# 4. glmark2-es2-drm (a sanity peer), one short scene
t=$(up)
timeout 180 glmark2-es2-drm --winsys-options drm-device=/dev/dri/card0 -b clear:duration=0.5 >"$R/glmark2.log" 2>&1
echo $? >"$R/glmark2.rc"
say "glmark2-es2-drm rc $(cat "$R/glmark2.rc") in $(awk "BEGIN { print $(up) - $t }") s"
# 4b. two outputs from one process (--outputs): QEMU's second head is
#    enabled by the host (its own VNC server, head=1, asks for ${W}x$H:
#    Virtual-2 becomes connected with that preferred mode).  A wall's row
#    (--outputs all --wall 2x1 --tile 0,0 --bezel 16): a screendump of each
#    head; Virtual-2 forced off (sysfs status) while it runs: said once,
#    Virtual-1 goes on flipping; back (detect): Virtual-2 modeset again, a
#    screendump of it.  Then a mirror (no --wall, a list of names): a
#    screendump of each head.  Virtual-2 is left forced off for what
#    follows (one connector, as before).  wall-counts.txt: presented/shown
#    when Virtual-2 went, later while it is off, when it is back.
st2=/sys/class/drm/card0-Virtual-2/status
NOMODE=$(echo "$ARGS" | sed 's/--mode [^ ]*//')
# lcounts LOG: the last "N presented, M shown" of an --fps-report log
lcounts() { grep -oE '[0-9]+ presented, [0-9]+ shown' "$1" | tail -1 | awk '{print $1, $3}'; }
# lwait LOG FIELD MIN SECONDS: until the log's last report's field (1
# presented, 2 shown) reaches MIN, while $pid lives
lwait() {
	n=0
	while [ $n -lt $(($4 * 10)) ] && kill -0 $pid 2>/dev/null; do
		[ "$(lcounts "$1" | awk -v f="$2" '{print $f}')" -ge "$3" ] 2>/dev/null && return 0
		sleep 0.1
		n=$((n + 1))
	done
	return 1
}
t=$(up)
shot "head1-${W}x$H"
n=0
while [ "$(cat $st2 2>/dev/null)" != connected ] && [ $n -lt 300 ]; do sleep 0.1; n=$((n + 1)); done
say "Virtual-2: $(cat $st2 2>/dev/null), modes $(head -2 /sys/class/drm/card0-Virtual-2/modes 2>/dev/null | tr '\n' ' ')"
"$BIN" --platform gbm $NOMODE --outputs all --wall 2x1 --tile 0,0 --bezel 16 --count 0 --fps-report 0.01 >"$R/wall.log" 2>&1 &
pid=$!
# (the first frame is a blocking modeset: on screen once it is presented)
if wait_line "$R/wall.log" ' [1-9] presented|[0-9][0-9]+ presented' 400 $pid; then
	shot wall0
	shot h1-wall1
	state wall
	echo off >$st2
	wait_line "$R/wall.log" 'Virtual-2 on /dev/dri/card0 disconnected' 60 $pid
	lwait "$R/wall.log" 1 $(($(lcounts "$R/wall.log" | cut -d' ' -f1) + 1)) 120
	c0=$(lcounts "$R/wall.log")
	lwait "$R/wall.log" 2 $(($(echo "$c0" | cut -d' ' -f2) + 2)) 120
	c1=$(lcounts "$R/wall.log")
	shot wall0-off
	echo detect >$st2
	wait_line "$R/wall.log" 'Virtual-2 on /dev/dri/card0 connected again' 60 $pid
	c2=$(lcounts "$R/wall.log")
	lwait "$R/wall.log" 2 $(($(echo "$c2" | cut -d' ' -f2) + 1)) 120
	printf '%s\n%s\n%s\n' "$c0" "$c1" "$c2" >"$R/wall-counts.txt"
	shot h1-wall1-back
	stop_app TERM wall
else
	say "isoterra presented no frames (--outputs all, a wall)"
	stop_app KILL wall
fi
say "two outputs, a wall's row, unplug and back: rc $(cat "$R/wall.rc") in $(awk "BEGIN { print $(up) - $t }") s"
t=$(up)
"$BIN" --platform gbm $NOMODE --outputs Virtual-1,Virtual-2 --rotate 270 --count 0 --fps-report 0.01 >"$R/mirror.log" 2>&1 &
pid=$!
if wait_line "$R/mirror.log" ' [1-9] presented|[0-9][0-9]+ presented' 400 $pid; then
	shot mirror0
	shot h1-mirror1
	stop_app TERM mirror
else
	say "isoterra presented no frames (--outputs, a mirror)"
	stop_app KILL mirror
fi
# a connector that is not there: one line naming it
"$BIN" --platform gbm $NOMODE --outputs Virtual-1,HDMI-A-9 --count 0 >"$R/badout.log" 2>&1
echo $? >"$R/badout.rc"
echo off >$st2
say "two outputs, a mirror: rc $(cat "$R/mirror.rc") in $(awk "BEGIN { print $(up) - $t }") s; Virtual-2 forced $(cat $st2)"

# 5. the display unplugged and plugged back (sysfs status) while isoterra
#    runs: frames go on unshown, then it modesets again; a screendump once
#    it is back.  hotplug-counts.txt: presented/shown when unplugged, after
#    frames went on unplugged, when plugged back.  Then, in the same run, a
#    new preferred mode (another monitor, or one that asks for another
#    size: the host resizes QEMU's display over VNC, the kernel sends a
#    hotplug event): it modesets the new mode and renders at its size; a
#    screendump then.  No --mode: it follows the preferred mode (320x240 at
#    first).  The connector keeps the new mode for what follows.  The panel
#    turned 90 degrees (--rotate 90): the turn holds through the modesets.
st=$(ls -d /sys/class/drm/card0-*/status | head -1)
NOMODE=$(echo "$ARGS" | sed 's/--mode [^ ]*//')
counts() { grep -oE '[0-9]+ presented, [0-9]+ shown' "$R/hotplug.log" | tail -1 | awk '{print $1, $3}'; }
# wait_count FIELD MIN SECONDS: until the last report's field (1 presented,
# 2 shown) reaches MIN
wait_count() {
	n=0
	while [ $n -lt $(($3 * 10)) ] && kill -0 $pid 2>/dev/null; do
		[ "$(counts | awk -v f="$1" '{print $f}')" -ge "$2" ] 2>/dev/null && return 0
		sleep 0.1
		n=$((n + 1))
	done
	return 1
}
t=$(up)
"$BIN" --platform gbm $NOMODE --rotate 90 --count 0 --fps-report 0.01 >"$R/hotplug.log" 2>&1 &
pid=$!
if wait_line "$R/hotplug.log" ' [2-9] presented|[0-9][0-9]+ presented' 400 $pid; then
	echo off >"$st"
	wait_line "$R/hotplug.log" 'disconnected' 600 $pid
	# the frame that noticed is reported after the line: counts from the next
	wait_count 1 $(($(counts | cut -d' ' -f1) + 1)) 600
	c0=$(counts)
	wait_count 1 $(($(echo "$c0" | cut -d' ' -f1) + 2)) 600
	c1=$(counts)
	echo detect >"$st"
	wait_line "$R/hotplug.log" 'connected again' 600 $pid
	c2=$(counts)
	wait_count 2 $(($(echo "$c2" | cut -d' ' -f2) + 2)) 600
	printf '%s\n%s\n%s\n' "$c0" "$c1" "$c2" >"$R/hotplug-counts.txt"
	shot back
	say "plugged back, shown at $(awk "BEGIN { print $(up) - $t }") s"
	shot "resize-${RW}x$RH"
	if wait_line "$R/hotplug.log" "changed its mode: modesetting ${RW}x$RH" 600 $pid; then
		wait_count 2 $(($(counts | cut -d' ' -f2) + 2)) 600
		shot resized
	fi
	stop_app TERM hotplug
else
	say "isoterra presented no frames (hotplug)"
	stop_app KILL hotplug
fi
echo detect >"$st"
say "hotplug and resize run rc $(cat "$R/hotplug.rc") in $(awk "BEGIN { print $(up) - $t }") s; modes now: $(cat /sys/class/drm/card0-*/modes 2>/dev/null | head -3 | tr '\n' ' ')"

# 6. clear errors: a mode the connector does not offer; then the connector
#    forced off (sysfs status): no connected display -> gbm fails with one
#    line, auto falls back to headless
# (--out in the results folder: the working folder is read-only, and the
# outputs are checked before the platform)
# isoterra --probe of the kiosk's job (the preferred mode, which the resize
# above changed): the card, its connector and modes,
# DRM master; 0 with the display connected, 1 with it off (below)
"$BIN" --probe --platform gbm $NOMODE --count 0 --results "$R/probe-on.json" >"$R/probe-on.txt" 2>"$R/probe-on.err"
echo $? >"$R/probe-on.rc"
"$BIN" --platform gbm --mode 123x45 $(echo "$ARGS" | sed 's/--mode [^ ]*//') --out "$R/badmode.png" >"$R/badmode.log" 2>&1
echo $? >"$R/badmode.rc"
echo off >"$st"
"$BIN" --probe --platform gbm $NOMODE --count 0 --results "$R/probe-off.json" >"$R/probe-off.txt" 2>"$R/probe-off.err"
echo $? >"$R/probe-off.rc"
"$BIN" --platform gbm $ARGS --out "$R/nodisplay.png" >"$R/nodisplay.log" 2>&1
echo $? >"$R/nodisplay.rc"
# (--count 0 makes a headless pick fail before any rendering, naming it)
"$BIN" --platform auto $ARGS --count 0 >"$R/auto-off.log" 2>&1
echo $? >"$R/auto-off.rc"
echo detect >"$st"
say "connector $st: $(cat "$st") again"

: >"$R/done"
