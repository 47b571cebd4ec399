#!/bin/sh
# isoterra — a handheld's rotated panel and power care (docs/HANDHELD.md).
# Rotation: --rotate 90, 180 and 270 give the upright picture turned
# clockwise onto the output (turned back, byte for byte the upright
# render), at the output's size (PNG and the Y4M header), the OSD turned
# with it.
# Power, with a fake power supply class
# folder ($ISOTERRA_POWER_SUPPLY, as /sys/class/power_supply lays it out):
#   - a battery at 42 % discharging: the results file names it, the OSD
#     shows it in the top-right corner (only there: the rest of the picture
#     is the one without a battery), no low-power profile;
#   - at 10 %: the low-power profile holds (logged; the results: low_power,
#     the 20 fps cap), and the world is drawn at its quality floor (another
#     picture than at 42 %, the OSD aside);
#   - at 10 % but charging (status, or a mains supply online): no profile;
#   - capacity missing: energy_now / energy_full; a battery not present is
#     no battery;
#   - an offline render without the folder named reads no battery (the
#     same picture as ever on a laptop).
# A third argument "quick" (the sanitizer build) draws the world smaller
# and nearer: the same checks on fewer pixels and blocks.
BIN=${1:-${ISOTERRA_BIN:-./build/isoterra}}
IMGCMP=${2:-$(dirname "$BIN")/tests/imgcmp}
QUICK=${3:-}
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
. "$(dirname "$0")/cli_lib.sh"
cd "$T" || exit 1

supply() { # pct status [mains-online] [energy]
	rm -rf ps
	mkdir -p ps/BAT0 ps/AC
	echo Battery >ps/BAT0/type
	if [ "${4:-}" = energy ]; then
		echo $(($1 * 300)) >ps/BAT0/energy_now
		echo 30000 >ps/BAT0/energy_full
	else
		echo "$1" >ps/BAT0/capacity
	fi
	echo "$2" >ps/BAT0/status
	echo Mains >ps/AC/type
	echo "${3:-0}" >ps/AC/online
}
WORLD="--scene world --size 320x180 --count 2"
LEFT=0,0,200,180 # left of the battery's box
if [ "$QUICK" = quick ]; then
	WORLD="--scene world --size 160x90 --count 1 --view-distance 24"
	LEFT=0,0,80,90
fi
SMALL="--size 96x64 --grid 16" # what the supply reads, not the picture
run() { # out args...: a render with the fake supply and --results
	out=$1
	shift
	ISOTERRA_POWER_SUPPLY=$T/ps "$BIN" --results "$out.json" --out "$out.png" "$@" \
		>"$out.log" 2>&1 || bad "isoterra $*: $(cat "$out.log")"
}
field() { # file key: the power object's value
	sed -n "s/.*\"power\": {.*\"$2\": \([^,}]*\).*/\1/p" "$1"
}
want() { # what got expected
	if [ "$2" = "$3" ]; then ok; else bad "$1: $2, want $3"; fi
}

"$BIN" $WORLD --results none.json --out none.png >none.log 2>&1 || bad "plain run: $(cat none.log)"
want "no folder named: battery" "$(field none.json battery_percent)" null

supply 42 Discharging
run b42 $WORLD
want "42 %: percent" "$(field b42.json battery_percent)" 42
want "42 %: status" "$(field b42.json battery_status)" '"Discharging"'
want "42 %: low power" "$(field b42.json low_power)" false
# the OSD: the top-right corner differs, the rest is the picture without it
if "$IMGCMP" none.png b42.png --max-mean 0 --max-frac 0 >/dev/null; then
	bad "the battery's OSD is not in the picture"
else
	ok
fi
# left of the box: untouched
if line=$("$IMGCMP" none.png b42.png --region $LEFT --max-mean 0 --max-frac 0); then
	ok
else
	bad "the battery's OSD is not only in the top-right corner: $line"
fi

supply 10 Discharging
run b10 $WORLD
want "10 %: low power" "$(field b10.json low_power)" true
want "10 %: the cap" "$(field b10.json frame_cap_fps)" 20.000
grep -q "the low-power profile holds" b10.log && ok || bad "10 %: no log line: $(cat b10.log)"
# the quality floor: another picture (render scale 0.5, less AO ...)
if "$IMGCMP" b42.png b10.png --max-mean 1 --max-frac 0.05 >/dev/null; then
	bad "10 %: the low-power picture is the full-quality one"
else
	ok
fi

supply 10 Charging
run c10 $SMALL
want "10 % charging: low power" "$(field c10.json low_power)" false
supply 10 Discharging 1
run m10 $SMALL
want "10 % on mains: low power" "$(field m10.json low_power)" false
supply 50 Discharging 0 energy
run e50 $SMALL
want "energy_now / energy_full" "$(field e50.json battery_percent)" 50
supply 10 Discharging
echo 0 >ps/BAT0/present
run p0 $SMALL
want "a battery not present" "$(field p0.json battery_percent)" null

# ---- rotation -----------------------------------------------------------------
R="--grid 32 --cam-spin 0"
supply 42 Discharging
ISOTERRA_POWER_SUPPLY=$T/ps "$BIN" $R --size 120x80 --out up.png >up.log 2>&1 || bad "upright: $(cat up.log)"
for deg in 90 180 270; do
	size=80x120
	[ $deg = 180 ] && size=120x80
	if ISOTERRA_POWER_SUPPLY=$T/ps "$BIN" $R --size $size --rotate $deg --out r$deg.png >r.log 2>&1; then
		if line=$("$IMGCMP" up.png r$deg.png --unturn $deg --max-mean 0 --max-frac 0); then
			ok
		else
			bad "--rotate $deg turned back is not the upright picture (the OSD with it): $line"
		fi
	else
		bad "--rotate $deg: $(cat r.log)"
	fi
done
# the Y4M stream has the output's size
if "$BIN" $R --size 80x120 --rotate 90 --count 2 --out r.y4m >r.log 2>&1; then
	head -c 40 r.y4m | grep -q "^YUV4MPEG2 W80 H120 " && ok || bad "--rotate 90 Y4M header: $(head -c 40 r.y4m)"
else
	bad "--rotate 90 to Y4M: $(cat r.log)"
fi

echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
