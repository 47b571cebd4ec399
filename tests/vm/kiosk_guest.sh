#!/bin/sh
# isoterra — inside the kiosk-unit VM (tests/vm/kiosk_unit.sh), run by
# systemd as isoterra-vmtest.service beside the installed, enabled
# isoterra-kiosk.service.  Writes "ok: ..." / "FAIL: ..." lines to
# /vmtest/guest.log, asks the host for screendumps (/vmtest/req-NAME, the
# host answers ack-NAME) and powers the VM off.
R=/vmtest
U=isoterra-kiosk.service
up() { cut -d. -f1 /proc/uptime; }
exec >>"$R/guest.log" 2>&1
ok() { echo "ok: $*"; }
bad() { echo "FAIL: $*"; }
prop() { systemctl show -P "$1" "$U"; }
shot() {
	: >"$R/req-$1"
	n=0
	while [ ! -e "$R/ack-$1" ] && [ $n -lt 300 ]; do sleep 0.2; n=$((n + 1)); done
	[ -e "$R/ack-$1" ] || bad "no screendump $1 from the host"
}
# active (Type=notify: "activating" until the program sends READY=1)
wait_active() { # seconds
	n=0
	while [ "$(systemctl is-active "$U")" != active ] && [ $n -lt "$1" ]; do sleep 1; n=$((n + 1)); done
	[ "$(systemctl is-active "$U")" = active ]
}
t0=$(cut -d. -f1 /proc/uptime)
echo "guest: $(systemctl --version | head -1), kernel $(uname -r), up $t0 s"

# 1. READY=1
if wait_active 400; then
	ok "READY=1: $U active at $(cut -d. -f1 /proc/uptime) s of uptime, status '$(prop StatusText)'"
else
	bad "$U not active: $(systemctl is-active "$U"), $(prop Result); $(journalctl -b -u "$U" --no-pager | tail -15)"
fi
id=$(id isoterra)
pid=$(prop MainPID)
grep -q '^Uid:.*\b'"$(id -u isoterra)"'\b' "/proc/$pid/status" 2>/dev/null && ok "runs as $id" ||
	bad "main process $pid is not user isoterra: $(grep -E '^(Uid|Gid)' "/proc/$pid/status" 2>&1)"
# 2. the watchdog pings (WatchdogSec/2 apart) and the frames advance
w1=$(prop WatchdogTimestampMonotonic)
s1=$(prop StatusText)
shot kiosk-a
sleep "${WAIT_WATCHDOG:-12}"
w2=$(prop WatchdogTimestampMonotonic)
s2=$(prop StatusText)
shot kiosk-b
[ "${w1:-0}" -gt 0 ] && [ "${w2:-0}" -gt "$w1" ] && ok "watchdog pings: WatchdogTimestamp $w1 -> $w2 us (WatchdogUSec $(prop WatchdogUSec))" ||
	bad "no watchdog ping seen: WatchdogTimestampMonotonic '$w1' -> '$w2'"
f1=$(echo "$s1" | awk '{print $1+0}')
f2=$(echo "$s2" | awk '{print $1+0}')
[ "$f2" -gt "$f1" ] && ok "frames advance: '$s1' -> '$s2'" || bad "frames do not advance: '$s1' -> '$s2'"
# 3. a knob turn changes the picture: the gpio-sim chip "knobs"
#    (isoterra-vmtest-gpio.service made it before the unit started;
#    /vmtest/gpio.env: CHIP, SYS) as the board's knobs, a line driven by
#    writing its sysfs "pull".  The unit opened the chip through its node
#    (group gpio, mode 0660, from the udev rule) in its own sandbox.  The
#    pause button freezes the orbit: two screendumps, the same to the byte
#    (the host compares them); then encoder 2 turns two detents (fov 40 ->
#    42) and the next screendump differs: the knob's doing, the clock stands
#    still.  The unit's knob log (kiosk.conf's knob_log, in its state
#    folder) says when each change is taken (polled: cheap, journalctl under
#    TCG is not), the journal is checked once at the end.  A change shows a
#    frame after it is taken, and a frame takes a second or two under TCG:
#    the waits after a log line leave it that.
tk=$(up)
CHIP='' SYS=''
# shellcheck disable=SC1091 # written in the guest
[ -r "$R/gpio.env" ] && . "$R/gpio.env"
if [ -z "$CHIP" ]; then
	bad "no gpio-sim chip: $(cat "$R/gpio.log" 2>&1)"
else
	node=$(stat -c '%G %a' "/dev/$CHIP" 2>&1)
	[ "$node" = "gpio 660" ] && ok "knobs: /dev/$CHIP (gpio-sim, label knobs): group gpio, mode 0660" ||
		bad "knobs: /dev/$CHIP is '$node', want 'gpio 660'"
fi
KLOG=/var/lib/isoterra/knob.log
nk() { if [ -f $KLOG ]; then wc -l <$KLOG; else echo 0; fi; }
waitk() { # the knob log at $1 lines, at most $2 seconds
	end=$(($(up) + $2))
	while [ "$(nk)" -lt "$1" ] && [ "$(up)" -lt $end ]; do sleep 0.25; done
	[ "$(nk)" -ge "$1" ]
}
# 100 ms between level changes: see line() in gpio_knobs_guest.sh
line() { [ -n "$SYS" ] && echo "pull-$2" >"$SYS/sim_gpio$1/pull"; sleep 0.1; } # line up|down
press() { line 2 down; sleep 0.1; line 2 up; } # the pause button (active-low)
cw() { line 1 up; line 0 up; line 1 down; line 0 down; } # a detent forward: 00 01 11 10 00
k0=$(nk)
press
waitk $((k0 + 1)) 30 || bad "pause button: nothing in the knob log in 30 s"
sleep 2
shot paused-a
sleep 2
shot paused-b
ta=$(up)
cw
cw
waitk $((k0 + 3)) 30 || bad "encoder: not two changes in the knob log in 30 s"
tb=$(up)
sleep 3
shot knob
press
waitk $((k0 + 4)) 30 || bad "pause button again: nothing in the knob log in 30 s"
got=$(sed -n "$((k0 + 1)),\$p" $KLOG | tr '\n' ',')
[ "$got" = "paused,fov 41,fov 42,running," ] && ok "knob log: $got (the turn taken in $((tb - ta)) s)" ||
	bad "knob log: '$got', want 'paused,fov 41,fov 42,running,'"
j=$(journalctl -b -u "$U" --no-pager -o cat | grep -E "gpio: |knob: " | sed 's/^isoterra: [a-z]*: //' | tr '\n' ',')
case "$j" in
*"gpio: $CHIP (knobs) ready,"*"knob: paused,knob: fov = 41,knob: fov = 42,knob: running,"*)
	ok "the unit's journal: ${j%,}" ;;
*) bad "the unit's journal: '$j', want gpio: $CHIP (knobs) ready, then paused, fov = 41, 42, running" ;;
esac
echo "guest: the knob checks took $(($(up) - tk)) s"
# 4. SIGKILL: systemd restarts it (Restart=always), NRestarts counts it
r1=$(prop NRestarts)
systemctl kill -s KILL "$U"
n=0
while [ "$(prop MainPID)" = "$pid" ] && [ $n -lt 30 ]; do sleep 1; n=$((n + 1)); done
sleep 3
if wait_active 300; then
	r2=$(prop NRestarts)
	[ "$r2" -eq $((r1 + 1)) ] && ok "after SIGKILL: restarted (NRestarts $r1 -> $r2), active again, main PID $pid -> $(prop MainPID)" ||
		bad "after SIGKILL: NRestarts $r1 -> $r2"
else
	bad "after SIGKILL: not active again: $(systemctl is-active "$U"); $(journalctl -b -u "$U" --no-pager | tail -10)"
fi
# 5. stopped: the console is back on the display
systemctl stop "$U"
sleep 2
shot console
# 6. its files: the state and cache folders are its own, nothing else is
#    writable.  The packaged unit, sandbox and all, as kiosk_unit.sh made
#    copies of it: isoterra-wtest-N.service runs one headless frame to
#    --out PATH (its state folder: written; a folder of mode 1777 in /etc:
#    refused by the sandbox alone); isoterra-wprobe.service tries to create a file in each
#    folder (a shell, in the same sandbox) and says what happened.
for t in 1:/var/lib/isoterra/w.png:yes 2:/etc/isoterra-open/w.png:no; do
	n=${t%%:*}
	t=${t#*:}
	f=${t%:*}
	want=${t#*:}
	systemctl start "isoterra-wtest-$n.service" >/dev/null 2>&1
	rc=$?
	why=$(journalctl -b -u "isoterra-wtest-$n.service" --no-pager -o cat | grep -m1 -iE "read-only|permission denied|cannot|error")
	if [ "$want" = yes ]; then
		[ $rc -eq 0 ] && [ -s "$f" ] && ok "isoterra --out $f: written" || bad "isoterra --out $f: rc $rc: $why"
	else
		# a folder of mode 1777: only the sandbox refuses it
		[ $rc -ne 0 ] && [ ! -e "$f" ] && echo "$why" | grep -q "Read-only file system" &&
			ok "isoterra --out $f: refused: $why" || bad "isoterra --out $f: rc $rc, '$why' (want Read-only file system)"
	fi
done
systemctl start isoterra-wprobe.service
journalctl -b -u isoterra-wprobe.service --no-pager -o cat | grep -E '^(writable|refused) ' >"$R/wprobe.txt"
# DIR:writable, DIR:refused (any reason: the user's own permissions may
# be enough), DIR:rofs (refused by the sandbox alone: "Read-only file
# system" where the user may write: kiosk_unit.sh made each *-open folder
# mode 1777), DIR:private (PrivateTmp: writable, unseen outside), DIR:any
# (a note: /dev/shm is a tmpfs of its own, but RemoveIPC= empties the
# real one of the user's files too, so outside it proves nothing)
for t in /var/lib/isoterra:writable /var/cache/isoterra:writable /etc:refused /etc/isoterra:refused \
	/usr/local:refused /var/log:refused /root:refused /etc/isoterra-open:rofs /usr/local/isoterra-open:rofs \
	/var/lib/isoterra-open:rofs /srv/isoterra-open:rofs /run/lock:rofs /home/isoterra-open:refused \
	/var/tmp:private /tmp:private /dev/shm:any; do
	d=${t%:*}
	want=${t#*:}
	l=$(grep -m1 "^[a-z]* $d:" "$R/wprobe.txt")
	# PrivateTmp: writable, but the system's /tmp, /var/tmp never see it
	[ "$want" = private ] && [ "${l%% *}" = writable ] && [ ! -e "$d/isoterra-wprobe" ] && l="private $l"
	case "$want:$l" in
	rofs:*"Read-only file system"*) ok "sandbox: $l" ;;
	rofs:*) bad "sandbox: $d: want 'Read-only file system', got '${l:-nothing}'" ;;
	any:*) echo "note: sandbox: ${l:-nothing}" ;;
	"$want:$want "*) ok "sandbox: $l" ;;
	*) bad "sandbox: $d: want $want, got '${l:-nothing}'" ;;
	esac
done
nprog=$(find /var/cache/isoterra/isoterra -type f 2>/dev/null | wc -l)
[ "$nprog" -gt 0 ] && ok "program cache: $nprog files in /var/cache/isoterra/isoterra" ||
	bad "nothing in the program cache /var/cache/isoterra/isoterra"
journalctl -b -u "$U" --no-pager -o short-monotonic | tail -40 >"$R/kiosk-journal.log"
echo "guest: done at $(cut -d. -f1 /proc/uptime) s"
: >"$R/done"
sync
systemctl poweroff --no-block 2>/dev/null || poweroff -f
