#!/bin/sh
# isoterra — guest side of gpio_knobs.sh (runs in the VM, chrooted into the
# host's file system; results in /run/res).  With GUEST_ROOT (env.sh) the
# app and hal_probe run in a chroot of that folder of the host (another
# distribution's build: its libgpiod, its Mesa), with the guest's /proc,
# /sys, /dev and /run; the gpio-sim side stays here.
. /run/res/env.sh
R=/run/res
fails=0
up() { cut -d. -f1 /proc/uptime; } # guest seconds (loops of sleeps drift under TCG)
ok() { echo "ok [$(up) s] $*"; }
bad() { echo "FAIL [$(up) s] $*"; fails=$((fails + 1)); }
die() { echo "FAIL [$(up) s] $*"; exit 1; }

if [ -n "$GUEST_ROOT" ]; then
	for m in proc sys dev; do mount --bind /$m "$GUEST_ROOT/$m" || die "mount /$m in $GUEST_ROOT"; done
	# /run: the results (/run/res), the shader cache, the keyboard's fifo
	if ! mount --rbind /run "$GUEST_ROOT/run" || ! mount -t tmpfs tmp "$GUEST_ROOT/tmp"; then
		die "mount /run, /tmp in $GUEST_ROOT"
	fi
	INROOT="chroot $GUEST_ROOT" # a command prefix, not a function: $! is the app's pid
	# (a new line first: the console's start is not one)
	printf '\nguest: app and probe run in %s (%s)\n' "$GUEST_ROOT" "$(. "$GUEST_ROOT/etc/os-release" && echo "$PRETTY_NAME")"
else
	INROOT=
fi

modprobe configfs || die "modprobe configfs"
insmod "$GPIOSIM" || die "insmod gpio-sim"
mkdir -p /sys/kernel/config 2>/dev/null
mount -t configfs none /sys/kernel/config 2>/dev/null
D=/sys/kernel/config/gpio-sim/knobs
# the chip's sysfs folder (the platform device is new each time it goes live)
find_sys() {
	CHIP=$(cat $D/bank0/chip_name)
	SYS=$(ls -d /sys/devices/platform/$(cat $D/dev_name)/$CHIP)
}
rest() { # encoders at rest (00), buttons released (pull-up, active-low)
	for l in 0 1 2 3; do echo pull-down >$SYS/sim_gpio$l/pull; done
	for l in 4 5; do echo pull-up >$SYS/sim_gpio$l/pull; done
}
# the app finds the chip by its label: the device (and its gpiochipN) is
# new each time the chip goes live
mkdir -p $D/bank0 && echo 8 >$D/bank0/num_lines && echo knobs >$D/bank0/label && echo 1 >$D/live || die "gpio-sim: cannot create the chip"
find_sys
rest
echo "guest: $CHIP at $SYS"
# One level change of a line, then a pause.  The kernel's v1 line events
# learn the edge's direction by reading the line's level in a threaded
# handler: when the guest's CPU is held off long enough (TCG on a loaded
# host), a line changed twice before that handler ran reports the same
# direction twice, the Gray sequence breaks and a detent is lost.  A line
# changes again two pauses later: 100 ms pauses tolerate stalls of the
# guest five times as long as 20 ms did (a detent was lost so once, beside
# a busy host, 2026-11-27: 'sun 1.2' never came).
line() { echo "pull-$2" >$SYS/sim_gpio$1/pull; sleep 0.1; } # line up|down
LOG=$R/knob.log
nlog() { if [ -f $LOG ]; then wc -l <$LOG; else echo 0; fi; }
# The app polls its inputs once per frame, and a frame of software
# rendering under TCG takes seconds (the first one, compiling the shaders,
# minutes without the shader cache): generous waits.
WAIT=${WAIT:-60}
# wait until the knob log has $1 lines, at most $2 (default $WAIT) seconds
waitlog() {
	end=$(($(up) + ${2:-$WAIT}))
	while [ "$(nlog)" -lt "$1" ] && [ "$(up)" -lt $end ]; do sleep 0.25; done
	[ "$(nlog)" -ge "$1" ]
}
waitapp() { # regex in the app log, at most $2 (default $WAIT) s; gives up early when the app is gone
	end=$(($(up) + ${2:-$WAIT}))
	while ! grep -q "$1" $R/app.log && [ "$(up)" -lt $end ] && kill -0 $APP 2>/dev/null; do sleep 0.25; done
	grep -q "$1" $R/app.log
}
# one detent forward: 00 -> 01 -> 11 -> 10 -> 00 (A = line $1, B = line $2)
cw() { line $2 up; line $1 up; line $2 down; line $1 down; }
ccw() { line $1 up; line $2 up; line $1 down; line $2 down; }
n=0
step() { # expect one more log line after the action: step "action" "expected line" [wait s]
	n=$((n + 1))
	$1
	if waitlog $n $3; then
		got=$(sed -n "${n}p" $LOG)
		[ "$got" = "$2" ] && ok "$1 -> $got" || bad "$1: got '$got', want '$2'"
	else
		bad "$1: no knob change within ${3:-$WAIT} s (want '$2')"
		n=$(nlog) # the next step expects the line after what did come
	fi
}
cat >$R/knobs.conf <<CONF
gpio_chip = knobs
gpio_retry = 0.5
enc1_a = 0
enc1_b = 1
enc2_a = 2
enc2_b = 3
enc_accel_max = 1
button_bias = as_is
button1_line = 4
button1_action = next
button2_line = 5
button2_action = pause
knob_params = ambient,sun,fov
knob_log = $LOG
gamepad = auto
gamepad_repeat_ms = 0
osd = false
ambient = 0.28
sun = 1.0
fov = 40
CONF
# a virtual keyboard (uinput -> evdev) for the same app: --keyboard evdev
modprobe evdev; modprobe uinput || die "modprobe uinput"
mkfifo /run/keys.fifo || die "mkfifo"
$INROOT "$PROBE" keys </run/keys.fifo >$R/keys.dev 2>$R/keys.log &
exec 3>/run/keys.fifo
end=$(($(up) + 30))
while [ ! -s $R/keys.dev ] && [ "$(up)" -lt $end ]; do sleep 0.25; done
KDEV=$(cat $R/keys.dev)
[ -c "$KDEV" ] && ok "virtual keyboard $KDEV" || die "no uinput keyboard: $(cat $R/keys.log)"
key() { echo "$1" >&3; }
# a crash leaves a core in the results folder (the host prints its backtrace)
ulimit -c unlimited
echo "/run/res/core.%e.%p" >/proc/sys/kernel/core_pattern
trap save_cache EXIT
# isoterra itself, headless, tiny frames (software rendering under TCG), one
# PNG per frame so the test sees it render, into the guest's tmpfs (FR:
# thousands of files written and listed over 9p cost the host CPU the
# guest needs); without the keyboard's fifo (fd 3), which must close when
# the test closes it
FR=/run/frames
mkdir -p $FR || die "mkdir $FR"
$INROOT "$BIN" --platform surfaceless --size 64x48 --grid 8 --count 1000000 --cam-spin 0 --no-water \
	--config $R/knobs.conf --keyboard evdev --keyboard-evdev $KDEV --out "$FR/f%d.png" >$R/app.out 2>$R/app.log 3>&- &
APP=$!
waitapp "gpio: $CHIP (knobs) ready" ${WAIT_FIRST:-600} && ok "app opened the chip" || die "app did not open $CHIP: $(cat $R/app.log)"
# which libgpiod the app runs on (1.6: libgpiod.so.2, 2.x: libgpiod.so.3)
lib=$(grep -o 'libgpiod\.so\.[0-9]*' /proc/$APP/maps | sort -u | tr '\n' ' ' | sed 's/ $//')
echo "guest: the app maps ${lib:-no libgpiod}"
if [ -n "$EXPECT_LIBGPIOD" ]; then
	[ "$lib" = "$EXPECT_LIBGPIOD" ] && ok "app runs on $EXPECT_LIBGPIOD" || bad "app maps '$lib', not $EXPECT_LIBGPIOD"
fi
# the first frame compiles every shader (minutes under TCG without the cache)
# (a sequence's frames are staged as f<N>.png.XXXXXX and renamed only when
# the run ends well: a staged frame counts)
frames() { ls $FR | grep -c '^f[0-9]*\.png'; }
waitframes() { # at least $1 frames, at most $2 s
	end=$(($(up) + $2))
	while [ "$(frames)" -lt "$1" ] && [ "$(up)" -lt $end ] && kill -0 $APP 2>/dev/null; do sleep 0.5; done
	[ "$(frames)" -ge "$1" ]
}
t0=$(up)
waitframes 2 ${WAIT_FIRST:-600} && ok "first frames rendered ($(($(up) - t0)) s)" ||
	die "no frames in ${WAIT_FIRST:-600} s: $(tail -3 $R/app.log)"
# isoterra --probe of the same job (its programs from the cache the app just
# filled), with the device in three states: busy (the app holds the lines),
# free, gone.  probe EXPECTED_RC NAME "regex of the last line"
PROBE_ARGS="--platform surfaceless --size 64x48 --grid 8 --cam-spin 0 --no-water --config $R/knobs.conf"
probe() {
	$INROOT "$BIN" --probe $PROBE_ARGS --results $R/probe_$2.json >$R/probe_$2.txt 2>$R/probe_$2.err
	prc=$?
	last=$(tail -n 1 $R/probe_$2.txt)
	[ $prc -eq $1 ] && echo "$last" | grep -q "$3" && ok "--probe ($2): exit $prc, $last" ||
		bad "--probe ($2): exit $prc, want $1 and '$3': $last $(tail -n 2 $R/probe_$2.err)"
}
probe 1 busy "NOT run.*enc1_a: $CHIP line 0 cannot be requested: Device or resource busy"

step "cw 2 3" "ambient 0.29"
step "cw 2 3" "ambient 0.3"
step "cw 2 3" "ambient 0.31"
step "ccw 2 3" "ambient 0.3"
step "cw 0 1" "select sun"
step "cw 2 3" "sun 1.1" # one step: a tenth of the decade of its default (1.15)
step "cw 2 3" "sun 1.2"
press4() { line 4 down; sleep 0.1; line 4 up; }
step press4 "select fov"
step "ccw 2 3" "fov 39"
press5() { line 5 down; sleep 0.1; line 5 up; }
step press5 "paused"
step press5 "running"
step "ccw 0 1" "select sun"
step "cw 0 1" "select fov"

# the chip goes away while the app runs ...
echo 0 >$D/live
waitapp "gpiochip 'knobs' is gone" && ok "vanished chip reported" || bad "vanished chip not reported"
nf=$(frames)
waitframes $((nf + 2)) $WAIT && ok "frames rendered while the chip is gone ($nf -> $(frames))" ||
	bad "no frames rendered while the chip is gone"
kill -0 $APP 2>/dev/null && ok "app survives the chip going away" || bad "app died when the chip went away"
[ "$(grep -c "is gone" $R/app.log)" -eq 1 ] && ok "reported once" || bad "reported $(grep -c 'is gone' $R/app.log) times"
# ... and comes back
echo 1 >$D/live
find_sys
rest
waitapp "(knobs) is back" && ok "chip back ($CHIP): reopened" || bad "chip not reopened: $(tail -3 $R/app.log)"
step "cw 2 3" "fov 40"
# removed for good
echo 0 >$D/live
rmdir $D/bank0 $D && ok "chip removed (rmdir)" || bad "rmdir failed"
nf=$(frames)
waitframes $((nf + 2)) $WAIT && ok "frames rendered after the removal ($nf -> $(frames))" ||
	bad "no frames rendered after the chip's removal"
kill -0 $APP 2>/dev/null && ok "app survives the chip's removal" || bad "app died after rmdir"
# the keyboard drives the same actions (the chip is gone: keys still work)
step "key right" "select ambient"
step "key up" "ambient 0.31"
step "key down" "ambient 0.3"
step "key p" "paused"
step "key p" "running"
step "key left" "select fov"
step "key down" "fov 39"
# the keyboard goes away: reported, the app goes on
exec 3>&-
waitapp "keys: $KDEV: .*retrying" && ok "vanished keyboard reported" || bad "vanished keyboard not reported: $(tail -2 $R/app.log)"
nf=$(frames)
waitframes $((nf + 2)) $WAIT && ok "frames rendered after the keyboard went away" || bad "no frames after the keyboard went away"
# ... and comes back (a new uinput device takes the lowest free event node,
# the same one): reopened, keys work again
$INROOT "$PROBE" keys </run/keys.fifo >$R/keys2.dev 2>>$R/keys.log &
exec 3>/run/keys.fifo
end=$(($(up) + 30))
while [ ! -s $R/keys2.dev ] && [ "$(up)" -lt $end ]; do sleep 0.25; done
if [ "$(cat $R/keys2.dev)" = "$KDEV" ]; then
	waitapp "keys: $KDEV opened" && ok "keyboard back: reopened" || bad "keyboard not reopened: $(tail -2 $R/app.log)"
	step "key up" "fov 40"
else
	bad "the new virtual keyboard is '$(cat $R/keys2.dev)', not $KDEV"
fi
exec 3>&-
# a gamepad (uinput: sticks, triggers, a hat D-pad, buttons) plugged in
# while the app runs: found by its capabilities (the keyboard above is
# none), its D-pad selects and changes as the encoders do, select resets,
# start toggles the camera; the picture follows the value
mkfifo /run/pad.fifo || die "mkfifo"
newpad() { # newpad FILE: a virtual gamepad fed from fd 4, its node in FILE
	$INROOT "$PROBE" pad </run/pad.fifo >$1 2>>$R/pad.log &
	exec 4>/run/pad.fifo
	end=$(($(up) + 30))
	while [ ! -s $1 ] && [ "$(up)" -lt $end ]; do sleep 0.25; done
	PDEV=$(cat $1)
	[ -c "$PDEV" ] && ok "virtual gamepad $PDEV" || bad "no uinput gamepad: $(cat $R/pad.log)"
}
pad() { echo "$*" >&4; }
# the newest frame written whole (the newest of all may be being written)
lastframe() { ls $FR | sed -n 's/^f\([0-9]*\)\.png.*/\1/p' | sort -n | tail -2 | head -1; }
# the picture (md5) of frame $1 (no OSD: osd = false)
pic() { md5sum <"$(ls $FR/f$1.png* | head -1)" | cut -d' ' -f1; }
newpad $R/pad.dev
waitapp "gamepad: isoterra test pad ($PDEV) opened" && ok "gamepad plugged in: opened" ||
	bad "gamepad not opened: $(tail -2 $R/app.log)"
step "pad hat right" "select ambient"
step "pad hat up" "ambient 0.31"
nf0=$(frames) # a frame begun after this one has ambient 0.31
step "pad press start" "camera manual" # (the volume's camera is the orbit either way)
step "pad press start" "camera auto"
waitframes $((nf0 + 3)) $WAIT || bad "no frames after the change"
l=$(lastframe)
pic1=$(pic $l)
[ "$(pic $((l - 1)))" = "$pic1" ] && ok "ambient 0.31: the same picture in frames $((l - 1)) and $l" ||
	bad "the picture changes by itself (frames $((l - 1)), $l)"
step "pad press select" "ambient 0.28" # reset: the start-up value
nf1=$(frames)
# unplugged mid-run: reported once, the app goes on
exec 4>&-
waitapp "gamepad: isoterra test pad ($PDEV): .*waiting for a gamepad" && ok "unplugged gamepad reported" ||
	bad "unplugged gamepad not reported: $(tail -2 $R/app.log)"
nf=$(frames)
waitframes $((nf + 2)) $WAIT && ok "frames rendered after the gamepad went away" || bad "no frames after the gamepad went away"
waitframes $((nf1 + 2)) $WAIT
[ "$(pic $(lastframe))" != "$pic1" ] && ok "the picture changed with the knob (ambient 0.31 -> 0.28, frame $(lastframe))" ||
	bad "the same picture at ambient 0.31 and 0.28"
[ "$(grep -c "waiting for a gamepad" $R/app.log)" -eq 1 ] && ok "reported once" ||
	bad "reported $(grep -c 'waiting for a gamepad' $R/app.log) times"
# plugged in again: picked up, works
newpad $R/pad2.dev
end=$(($(up) + WAIT))
while [ "$(grep -c "gamepad: isoterra test pad .* opened" $R/app.log)" -lt 2 ] && [ "$(up)" -lt $end ]; do sleep 0.25; done
[ "$(grep -c "gamepad: isoterra test pad .* opened" $R/app.log)" -eq 2 ] && ok "gamepad plugged in again: opened" ||
	bad "gamepad not opened again: $(tail -2 $R/app.log)"
step "pad hat left" "select fov"
exec 4>&-
# the chip comes back with a line taken (a kernel hog on line 4, the first
# button): the app says so once, renders on and retries; once the line is
# free again the chip is back and its knobs work
mkdir $D $D/bank0 && echo 8 >$D/bank0/num_lines && echo knobs >$D/bank0/label &&
	mkdir $D/bank0/line4 $D/bank0/line4/hog && echo hog4 >$D/bank0/line4/hog/name &&
	echo input >$D/bank0/line4/hog/direction && echo 1 >$D/live || die "gpio-sim: cannot create the chip with a hog"
waitapp "line 4 of 'knobs' .*busy.*retrying" && ok "busy line reported: $(grep -m1 "line 4 of 'knobs'" $R/app.log)" ||
	bad "busy line not reported: $(tail -2 $R/app.log)"
nf=$(frames)
waitframes $((nf + 2)) $WAIT && ok "frames rendered while the line is busy" || bad "no frames while the line is busy"
[ "$(grep -c "(knobs) is back" $R/app.log)" -eq 1 ] && ok "not back while the line is busy" ||
	bad "'is back' $(grep -c "(knobs) is back" $R/app.log) times with line 4 busy"
echo 0 >$D/live && rmdir $D/bank0/line4/hog $D/bank0/line4 && echo 1 >$D/live || die "gpio-sim: cannot drop the hog"
find_sys
rest
end=$(($(up) + WAIT))
while [ "$(grep -c "(knobs) is back" $R/app.log)" -lt 2 ] && [ "$(up)" -lt $end ]; do sleep 0.25; done
[ "$(grep -c "(knobs) is back" $R/app.log)" -ge 2 ] && ok "line free: chip back ($CHIP)" ||
	bad "chip not back once the line was free: $(tail -3 $R/app.log)"
step "ccw 2 3" "fov 39"
kill -TERM $APP
wait $APP
rc=$?
# stopped before its last frame: 128 + SIGTERM, and no frame committed
[ $rc -eq 143 ] && grep -q "stopped by SIGTERM" $R/app.log && ok "app exits 143 on SIGTERM before its last frame" ||
	bad "app exit status $rc: $(tail -3 $R/app.log)"
[ "$(nlog)" -eq $n ] && ok "no unexpected knob changes ($n)" || bad "$(nlog) knob log lines, want $n: $(cat $LOG)"
# the probe with the chip free: every knob line can be requested
probe 0 free "the job would run"
grep -q "enc2_b: knobs line 3: can be requested" $R/probe_free.txt && grep -q "$CHIP, label 'knobs', 8 lines" $R/probe_free.txt &&
	ok "--probe lists the chip and its lines" || bad "--probe (free): $(grep -A12 '^GPIO' $R/probe_free.txt)"
# ... and with the chip gone: the first blocking reason names it
echo 0 >$D/live && rmdir $D/bank0 $D || bad "rmdir failed"
probe 1 gone "NOT run.*enc1_a: gpiochip 'knobs' not found"
# a flight steered by the gamepad: the world's manual camera (the
# autopilot's guard keeps it out of rock), a tiny world of 8^3-cell blocks,
# 3 frames; the left stick is held forward before the app starts (read as
# the pad's state when it opens): the camera moves between frames 1 and 2
# (with no input they are the same picture: frame time is frame / fps, the
# world waits for its blocks; checked on the host)
newpad $R/pad3.dev
pad y -32768
sleep 0.5 # the pad's state is set before the app opens it
WF=/run/wframes
mkdir -p $WF || die "mkdir $WF"
t0=$(up)
timeout 300 $INROOT "$BIN" --platform surfaceless --scene world --camera manual --size 64x48 --count 3 --block-cells 8 \
	--block-size 16 --lod-levels 1 --view-distance 32 --lod-distance 1 --fade-time 0 --no-water --antialias off \
	--ao-rays 0 --fly-speed 90 --gamepad auto --keyboard off --out "$WF/f%d.png" >$R/world.out 2>$R/world.log 3>&- 4>&-
rc=$?
exec 4>&-
[ $rc -eq 0 ] && ok "world: 3 frames ($(($(up) - t0)) s)" || bad "world: exit $rc: $(tail -3 $R/world.log)"
grep -q "gamepad: isoterra test pad ($PDEV) opened" $R/world.log && ok "world: the gamepad opened at the start" ||
	bad "world: gamepad not opened: $(tail -2 $R/world.log)"
[ -s $WF/f1.png ] && [ -s $WF/f2.png ] && ! cmp -s $WF/f1.png $WF/f2.png &&
	ok "world: the left stick forward, the picture moves (frames 1, 2)" || bad "world: the stick did not move the picture"
echo "guest: $fails failures"
[ $fails -eq 0 ]
