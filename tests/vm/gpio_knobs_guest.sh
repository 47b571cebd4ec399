#!/bin/sh
# isoterra — guest side of gpio_knobs.sh (runs in the VM, chrooted into the
# host's file system; results in /tmp/res).
. /tmp/res/env.sh
R=/tmp/res
fails=0
ok() { echo "ok $*"; }
bad() { echo "FAIL $*"; fails=$((fails + 1)); }
die() { echo "FAIL $*"; exit 1; }

modprobe configfs || die "modprobe configfs"
insmod "$GPIOSIM" || die "insmod gpio-sim"
mkdir -p /sys/kernel/config 2>/dev/null
mount -t configfs none /sys/kernel/config 2>/dev/null
D=/sys/kernel/config/gpio-sim/knobs
make_chip() {
	mkdir -p $D/bank0 && echo 8 >$D/bank0/num_lines && echo 1 >$D/live || die "gpio-sim: cannot create the chip"
	CHIP=$(cat $D/bank0/chip_name)
	SYS=$(ls -d /sys/devices/platform/$(cat $D/dev_name)/$CHIP)
	# encoders at rest (00), buttons released (pull-up, active-low)
	for l in 0 1 2 3; do echo pull-down >$SYS/sim_gpio$l/pull; done
	for l in 4 5; do echo pull-up >$SYS/sim_gpio$l/pull; done
}
make_chip
echo "guest: $CHIP at $SYS"
line() { echo "pull-$2" >$SYS/sim_gpio$1/pull; sleep 0.02; } # line up|down
LOG=$R/knob.log
nlog() { if [ -f $LOG ]; then wc -l <$LOG; else echo 0; fi; }
# wait until the knob log has $1 lines (the app polls once per frame)
waitlog() {
	i=0
	while [ "$(nlog)" -lt "$1" ] && [ $i -lt 100 ]; do sleep 0.1; i=$((i + 1)); done
	[ "$(nlog)" -ge "$1" ]
}
waitapp() { # regex in the app log
	i=0
	while ! grep -q "$1" $R/app.log && [ $i -lt 150 ]; do sleep 0.1; i=$((i + 1)); done
	grep -q "$1" $R/app.log
}
# one detent forward: 00 -> 01 -> 11 -> 10 -> 00 (A = line $1, B = line $2)
cw() { line $2 up; line $1 up; line $2 down; line $1 down; }
ccw() { line $1 up; line $2 up; line $1 down; line $2 down; }
n=0
step() { # expect one more log line after the action: step "action" "expected line"
	n=$((n + 1))
	$1
	if waitlog $n; then
		got=$(sed -n "${n}p" $LOG)
		[ "$got" = "$2" ] && ok "$1 -> $got" || bad "$1: got '$got', want '$2'"
	else
		bad "$1: no knob change within 10 s (want '$2')"
	fi
}
cat >$R/knobs.conf <<CONF
gpio_chip = /dev/$CHIP
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
knob_params = ambient,sun,octaves
knob_log = $LOG
CONF
"$BIN" knobs --config $R/knobs.conf --keyboard off >$R/app.out 2>$R/app.log &
APP=$!
waitapp "gpio: $CHIP .* ready" && ok "app opened the chip" || die "app did not open $CHIP: $(cat $R/app.log)"

step "cw 2 3" "ambient 0.29"
step "cw 2 3" "ambient 0.3"
step "cw 2 3" "ambient 0.31"
step "ccw 2 3" "ambient 0.3"
step "cw 0 1" "select sun"
step "cw 2 3" "sun 0.96"
step "cw 2 3" "sun 0.97"
press4() { line 4 down; sleep 0.1; line 4 up; }
step press4 "select octaves"
step "ccw 2 3" "octaves 8"
press5() { line 5 down; sleep 0.1; line 5 up; }
step press5 "paused"
step press5 "running"
step "ccw 0 1" "select sun"
step "cw 0 1" "select octaves"

# the chip goes away while the app runs ...
echo 0 >$D/live
waitapp "gpiochip '/dev/$CHIP' is gone" && ok "vanished chip reported" || bad "vanished chip not reported"
sleep 2
kill -0 $APP 2>/dev/null && ok "app survives the chip going away" || bad "app died when the chip went away"
[ "$(grep -c "is gone" $R/app.log)" -eq 1 ] && ok "reported once" || bad "reported $(grep -c 'is gone' $R/app.log) times"
# ... and comes back
echo 1 >$D/live
for l in 0 1 2 3; do echo pull-down >$SYS/sim_gpio$l/pull; done
for l in 4 5; do echo pull-up >$SYS/sim_gpio$l/pull; done
waitapp "$CHIP .* is back" && ok "chip back: reopened" || bad "chip not reopened: $(tail -3 $R/app.log)"
step "cw 2 3" "octaves 9"
# removed for good
echo 0 >$D/live
rmdir $D/bank0 $D && ok "chip removed (rmdir)" || bad "rmdir failed"
sleep 3
kill -0 $APP 2>/dev/null && ok "app survives the chip's removal" || bad "app died after rmdir"
kill -TERM $APP
wait $APP
rc=$?
[ $rc -eq 0 ] && ok "app exits 0 on SIGTERM" || bad "app exit status $rc: $(tail -3 $R/app.log)"
[ "$(nlog)" -eq $n ] && ok "no unexpected knob changes ($n)" || bad "$(nlog) knob log lines, want $n: $(cat $LOG)"
echo "guest: $fails failures"
[ $fails -eq 0 ]
