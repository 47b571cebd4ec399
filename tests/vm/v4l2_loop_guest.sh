#!/bin/sh
# isoterra — guest side of v4l2_loop.sh (runs in the VM, chrooted into the
# host's file system; results in /run/res).
. /run/res/env.sh
R=/run/res
fails=0
up() { cut -d. -f1 /proc/uptime; } # guest seconds
ok() { echo "ok $*"; }
bad() { echo "FAIL $*"; fails=$((fails + 1)); }
die() { echo "FAIL $*"; exit 1; }
WAIT=${WAIT:-400}

modprobe vivid n_devs=1 node_types=0x101 || die "modprobe vivid"
CAP= OUT=
for d in /sys/class/video4linux/video*; do
	case $(cat $d/name) in
	*vid-cap) CAP=/dev/${d##*/} ;;
	*vid-out) OUT=/dev/${d##*/} ;;
	esac
done
[ -c "$CAP" ] && [ -c "$OUT" ] || die "vivid nodes not found (cap '$CAP', out '$OUT')"
echo "guest: vivid capture $CAP, output $OUT"
# HDMI on both sides; the output keeps its DV timing, the capture input
# gets the same one (looping needs the same size and format on both sides)
v4l2-ctl -d $OUT --set-output=1 || die "VIDIOC_S_OUTPUT"
OW=$(v4l2-ctl -d $OUT --get-dv-timings | awk '/Active width:/ {print $3}')
OH=$(v4l2-ctl -d $OUT --get-dv-timings | awk '/Active height:/ {print $3}')
[ -n "$OW" ] && [ -n "$OH" ] || die "no DV timing on the output: $(v4l2-ctl -d $OUT --get-dv-timings 2>&1)"
v4l2-ctl -d $CAP --set-input=3 || die "VIDIOC_S_INPUT"
IDX=$(v4l2-ctl -d $CAP --list-dv-timings | awk -v W=$OW -v H=$OH '/Index:/ {i = $2; w = 0}
	$0 ~ "Active width: " W "$" {w = 1} $0 ~ "Active height: " H "$" && w {print i; exit}')
[ -n "$IDX" ] || die "the capture has no ${OW}x$OH DV timing: $(v4l2-ctl -d $CAP --list-dv-timings 2>&1 | head -12)"
v4l2-ctl -d $CAP --set-dv-bt-timings index=$IDX &&
	v4l2-ctl -d $CAP --set-fmt-video=width=$OW,height=$OH,pixelformat=YUYV,field=none &&
	v4l2-ctl -d $CAP --set-ctrl=loop_video=1 && v4l2-ctl -d $CAP --set-ctrl=osd_text_mode=2 ||
	die "configuring vivid failed"
echo "$OW $OH" >$R/size
# the app renders a quarter of that (software rendering in the guest is
# slow); vivid scales the output up to 4x
SW=$((OW / 4)) SH=$((OH / 4))
echo "guest: HDMI ${OW}x$OH on both sides (timing $IDX), the app renders ${SW}x$SH"
capture() { v4l2-ctl -d $CAP --stream-mmap=3 --stream-count=3 --stream-to="$1" 2>&1 | tail -1; }
capture $R/before.yuv
[ -s $R/before.yuv ] && ok "capture before the app: $(wc -c <$R/before.yuv) bytes" || die "capture failed"

# not an output: the capture node is refused with one clear message (bad
# configuration: exit 2)
"$BIN" --platform surfaceless --size 64x48 --grid 8 --count 2 --keyboard off --v4l2 $CAP \
	--out $R/refused.png >$R/refused.log 2>&1
rc=$?
[ $rc -eq 2 ] && grep -q "v4l2 $CAP .*not a video output" $R/refused.log &&
	ok "capture node refused: $(grep "error" $R/refused.log | head -1)" ||
	bad "capture node as --v4l2: rc $rc: $(cat $R/refused.log)"
# busy: another program streams to the output node; the app says so once
# and renders its frames anyway
v4l2-ctl -d $OUT --stream-out-mmap --stream-count=100000 >/dev/null 2>&1 &
OTHER=$!
sleep 2
"$BIN" --platform surfaceless --size 64x48 --grid 8 --count 2 --cam-spin 0 --no-water --keyboard off \
	--v4l2 $OUT --out $R/busy.png >$R/busy.log 2>&1
rc=$?
kill $OTHER
wait $OTHER
if [ $rc -eq 0 ] && [ -s $R/busy.png ] && grep -qi "busy" $R/busy.log; then
	ok "busy device reported, frames rendered: $(grep -i busy $R/busy.log | head -1)"
else
	bad "busy output: rc $rc: $(cat $R/busy.log)"
fi

# isoterra --probe (the same job's programs, from the cache the run above
# filled): the output and its formats; the capture node and a missing
# device block the job.  probe EXPECTED_RC NAME "regex of the last line" args
probe() {
	want=$1 name=$2 pat=$3
	shift 3
	"$BIN" --probe --platform surfaceless --size 64x48 --grid 8 --cam-spin 0 --no-water --keyboard off "$@" \
		--results $R/probe_$name.json >$R/probe_$name.txt 2>$R/probe_$name.err
	prc=$?
	last=$(tail -n 1 $R/probe_$name.txt)
	[ $prc -eq $want ] && echo "$last" | grep -q "$pat" && ok "--probe ($name): exit $prc, $last" ||
		bad "--probe ($name): exit $prc, want $want and '$pat': $last $(tail -n 2 $R/probe_$name.err)"
}
probe 0 output "the job would run" --v4l2 $OUT --v4l2-format YUYV
grep -q "^  $OUT: .*video output, formats .*YUYV" $R/probe_output.txt && grep -q -- "--v4l2 $OUT: writes YUYV" $R/probe_output.txt &&
	ok "--probe lists $OUT and its formats" || bad "--probe (output): $(grep -A4 '^V4L2' $R/probe_output.txt)"
probe 1 capture "NOT run.*--v4l2 $CAP .*is not a video output device" --v4l2 $CAP
probe 1 missing "NOT run.*--v4l2 /dev/video99: cannot open" --v4l2 /dev/video99

# the app streams to the output node until SIGTERM; its frames go to the
# guest's tmpfs (FR: thousands of files written and listed over 9p cost
# the host CPU the guest needs; see gpio_knobs_guest.sh)
FR=/run/frames
mkdir -p $FR || die "mkdir $FR"
"$BIN" --platform surfaceless --size ${SW}x$SH --grid 16 --count 1000000 --cam-spin 0 --no-water --keyboard off \
	--v4l2 $OUT --v4l2-format YUYV --v4l2-matrix bt601 --v4l2-fps 0 --out "$FR/frame%d.png" >$R/app.log 2>&1 &
APP=$!
# a sequence's frames are staged as frame<N>.png.XXXXXX, renamed only when
# the run ends well; frames are written in order, so every frame below the
# newest one is whole
fr() { ls $FR/frame$1.png $FR/frame$1.png.* 2>/dev/null | head -1; }
end=$(($(up) + WAIT))
while [ -z "$(fr 4)" ] && [ "$(up)" -lt $end ] && kill -0 $APP 2>/dev/null; do sleep 0.5; done
[ -n "$(fr 4)" ] || die "the app did not render 4 frames in $WAIT s: $(tail -5 $R/app.log)"
grep -q "v4l2: $OUT .* YUYV" $R/app.log && ok "$(grep "v4l2: $OUT" $R/app.log | head -1)" ||
	bad "output format not negotiated: $(cat $R/app.log)"
capture $R/cap.yuv
# the newest frame the app had written when the capture was taken
n=3
while [ -n "$(fr $((n + 2)))" ]; do n=$((n + 1)); done
cp "$(fr $n)" $R/ref.png # the app removes its staged frames when it stops
echo ref.png >$R/ref.name
[ -s $R/cap.yuv ] && ok "capture while the app streams: $(wc -c <$R/cap.yuv) bytes (frame $n)" || bad "capture failed"
cmp -s "$(fr 2)" $R/ref.png && ok "the app's frames are still (frame 2 = frame $n)" ||
	bad "the app's frames change (frame 2 != frame $n): the capture cannot be matched"
# the device goes away while the app streams: vivid's "Disconnect" control
# unregisters its nodes as a USB unplug would (ioctls fail with ENODEV) and
# registers them again once the last file handle is closed.  The app must
# report it, go on rendering, and stream again when the node is back.
frames() { ls $FR | grep -c '^frame[0-9]*\.png'; }
waitfor() { # regex in the app log, at most $2 s
	end=$(($(up) + $2))
	while ! grep -q "$1" $R/app.log && [ "$(up)" -lt $end ] && kill -0 $APP 2>/dev/null; do sleep 0.5; done
	grep -q "$1" $R/app.log
}
v4l2-ctl -d $CAP --set-ctrl=disconnect=1 || bad "vivid's disconnect control failed"
waitfor "v4l2: $OUT: .*No such device.*video output stopped" 120 &&
	ok "device gone reported: $(grep "video output stopped" $R/app.log | head -1)" ||
	bad "device gone not reported: $(tail -3 $R/app.log)"
nf=$(frames)
end=$(($(up) + 120))
while [ "$(frames)" -lt $((nf + 2)) ] && [ "$(up)" -lt $end ] && kill -0 $APP 2>/dev/null; do sleep 0.5; done
[ "$(frames)" -ge $((nf + 2)) ] && ok "frames rendered after the device went away ($nf -> $(frames))" ||
	bad "rendering stopped with the device"
waitfor "v4l2: $OUT .*(recovered)" 120 && ok "output resumed: $(grep "(recovered)" $R/app.log | head -1)" ||
	bad "output did not resume: $(tail -3 $R/app.log)"
# the looped frames are the app's again
sleep 5
capture $R/cap2.yuv
[ -s $R/cap2.yuv ] && ok "capture after the reconnection: $(wc -c <$R/cap2.yuv) bytes" || bad "capture after the reconnection failed"
# the driver unloaded while the app streams, and loaded again: meanwhile
# the node cannot be opened (reported once), then the app streams again.
# (vivid's disconnect first makes the app close the node, so the module
# can go; it re-registers its nodes once the last handle is closed)
v4l2-ctl -d $CAP --set-ctrl=disconnect=1 || bad "vivid's disconnect control failed"
end=$(($(up) + 120))
# The app retries every 2 s: on a slow guest (a loaded host) it can have
# the node back before rmmod gets its turn; then it is taken away again.
recovered() { grep -c "v4l2: $OUT .*(recovered)" $R/app.log; }
rec=$(recovered)
until rmmod vivid 2>/dev/null || [ "$(up)" -ge $end ]; do
	if [ "$(recovered)" -gt "$rec" ]; then
		rec=$(recovered)
		v4l2-ctl -d $CAP --set-ctrl=disconnect=1 2>/dev/null
	fi
	sleep 0.1
done
rec=$(recovered)
if lsmod | grep -q '^vivid '; then
	bad "vivid could not be unloaded: $(tail -2 $R/app.log)"
else
	waitfor "v4l2: $OUT: cannot open: No such file or directory; no video output, retrying" 60 &&
		ok "node gone reported: $(grep -m1 "cannot open: No such file" $R/app.log)" ||
		bad "missing node not reported: $(tail -3 $R/app.log)"
	modprobe vivid n_devs=1 node_types=0x101 && v4l2-ctl -d $OUT --set-output=1 || bad "vivid did not come back"
	end=$(($(up) + 120))
	while [ "$(recovered)" -le "$rec" ] && [ "$(up)" -lt $end ] && kill -0 $APP 2>/dev/null; do sleep 0.5; done
	[ "$(recovered)" -gt "$rec" ] &&
		ok "driver back: streaming again ($(grep "(recovered)" $R/app.log | tail -1))" ||
		bad "output did not resume after the reload: $(tail -3 $R/app.log)"
fi
kill -TERM $APP
wait $APP
rc=$?
# stopped before its last frame: 128 + SIGTERM, and no frame committed
[ $rc -eq 143 ] && grep -q "stopped by SIGTERM" $R/app.log && ok "app exits 143 on SIGTERM before its last frame" ||
	bad "app exit status $rc: $(tail -3 $R/app.log)"
grep "v4l2:" $R/app.log | tail -2
save_cache
echo "guest: $fails failures"
[ $fails -eq 0 ]
