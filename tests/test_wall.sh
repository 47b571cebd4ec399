#!/bin/sh
# isoterra — the video wall (docs/WALL.md):
#   - stitched equals whole: the tiles of 2x1 and 2x2 walls of the volume
#     scene and of the world (offline, same time and seed), each rendered
#     by its own process, match the same rectangles of one render of the
#     whole virtual screen (bezels included in its size, their pixels
#     skipped): PSNR >= 40 dB for every tile and for the stitched picture;
#   - --bezel-mm with --panel-mm is the same picture as the same gap in
#     pixels;
#   - the realtime clock: two processes started 0.3 s apart draw the same
#     picture for the same tick of CLOCK_REALTIME (a %d in --out is the
#     tick within --clock-period), and the first tick is the one the shell
#     read before starting them;
#   - refusals: a tile off the wall, a bad wall or bezel, bezel_mm without
#     panel_mm, a governor of its own on a wall, an unknown clock.
# With a third argument "quick" (the sanitizer builds: meson test wall_quick)
# only the last two parts: the options' code paths without the pictures.
BIN=${1:-${ISOTERRA_BIN:-./build/isoterra}}
IMGCMP=${2:-$(dirname "$BIN")/tests/imgcmp}
QUICK=${3:-}
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
MAX_MSG_LINES=2
NO_OUTPUT=out.png
. "$(dirname "$0")/cli_lib.sh"
cd "$T" || exit 1
[ -x "$IMGCMP" ] || { echo "imgcmp not built: $IMGCMP"; exit 1; }

render() { # out args...: one render, or a failure naming it
	out=$1
	shift
	if ! "$BIN" "$@" --out "$out" >"$T/log" 2>&1; then
		bad "isoterra $* --out $out: $(cat "$T/log")"
		return 1
	fi
}

# wall_check NAME COLS ROWS TW TH BX BY args...: the tiles against the whole
wall_check() {
	name=$1 cols=$2 rows=$3 tw=$4 th=$5 bx=$6 by=$7
	shift 7
	vw=$((cols * tw + (cols - 1) * bx)) vh=$((rows * th + (rows - 1) * by))
	render "$name-whole.png" --size "${vw}x${vh}" "$@" || return
	sum=0 n=0 r=0
	while [ $r -lt "$rows" ]; do
		c=0
		while [ $c -lt "$cols" ]; do
			tile=$name-$c-$r.png
			if render "$tile" --size "${tw}x${th}" --wall "${cols}x${rows}" --tile "$c,$r" --bezel "$bx,$by" "$@"; then
				x=$((c * (tw + bx))) y=$((r * (th + by)))
				if line=$("$IMGCMP" "$name-whole.png" "$tile" --at "$x,$y" --min-psnr 40); then
					ok
				else
					bad "$name: tile $c,$r against the whole at $x,$y: $line"
				fi
				# the stitched picture's mean square error, from each tile's
				rmse=$(echo "$line" | sed -n 's/.* rmse \([0-9.]*\) .*/\1/p')
				sum=$(echo "$sum $rmse" | awk '{ printf "%.6f", $1 + $2 * $2 }')
				n=$((n + 1))
			fi
			c=$((c + 1))
		done
		r=$((r + 1))
	done
	if [ $n -eq $((cols * rows)) ]; then
		psnr=$(echo "$sum $n" | awk '{ m = $1 / $2; if (m <= 0) print 99; else printf "%.1f", 20 * log(255 / sqrt(m)) / log(10) }')
		if awk "BEGIN { exit !($psnr >= 40) }"; then
			ok
			echo "$name: ${cols}x${rows} tiles of ${tw}x${th}, bezel $bx,$by: stitched PSNR $psnr dB"
		else
			bad "$name: stitched PSNR $psnr dB < 40"
		fi
	fi
}

VOL="--grid 64"
if [ "$QUICK" != quick ]; then
# every offline frame complete (all its blocks generated): a function of
# the camera, not of the frames before it (docs/WALL.md)
WORLD="--scene world --count 3 --gen-per-frame 10000"
wall_check volume2x1 2 1 112 84 12 0 $VOL
wall_check volume2x2 2 2 96 72 10 14 $VOL --cam-yaw 80
wall_check world2x1 2 1 112 63 12 0 $WORLD
wall_check world2x2 2 2 96 54 8 8 $WORLD --fly-height 4

fi

# the gap in millimetres: 112 px over 56 mm is 2 px/mm, 6 mm is 12 px
if render mm.png --size 112x84 --wall 2x1 --tile 1,0 --bezel-mm 6 --panel-mm 56x42 $VOL &&
	render px.png --size 112x84 --wall 2x1 --tile 1,0 --bezel 12 $VOL; then
	if cmp -s mm.png px.png; then ok; else bad "--bezel-mm 6 --panel-mm 56x42 is not --bezel 12"; fi
fi
# a wall's tile is not the picture without the wall (the frustum is off-axis)
if render one.png --size 112x84 $VOL && cmp -s one.png px.png; then
	bad "tile 1,0 of a 2x1 wall is the same picture as the whole screen"
else
	ok
fi

# ---- the realtime clock -------------------------------------------------------
if [ "$QUICK" != quick ]; then
# two processes 0.3 s apart, 2 ticks a second: the frames they share are
# the same picture (the volume: a function of time; the world: of time
# and seed, with complete frames and the fade-in of new blocks left out,
# docs/WALL.md)
clock_check() { # name args...
	name=$1
	shift
	mkdir -p "$name"
	"$BIN" "$@" --clock realtime --clock-period 20 --fps 2 --count 8 --out "$name/a%d.png" >"$name/a.log" 2>&1 &
	pa=$!
	sleep 0.3
	"$BIN" "$@" --clock realtime --clock-period 20 --fps 2 --count 8 --out "$name/b%d.png" >"$name/b.log" 2>&1 &
	pb=$!
	wait $pa || bad "$name: the first process failed: $(cat "$name/a.log")"
	wait $pb || bad "$name: the second process failed: $(cat "$name/b.log")"
	common=0 differ=0
	for a in "$name"/a*.png; do
		[ -e "$a" ] || continue
		b=$name/b${a#"$name"/a}
		[ -e "$b" ] || continue
		common=$((common + 1))
		cmp -s "$a" "$b" || { differ=$((differ + 1)); "$IMGCMP" "$a" "$b" >&2; }
	done
	if [ $common -ge 3 ] && [ $differ -eq 0 ]; then
		ok
		echo "$name: $common frames drawn by both processes for the same tick, all identical"
	else
		bad "$name: $common frames for the same tick, $differ of them differ (want >= 3, 0)"
	fi
	# each frame's number is the realtime tick it was drawn for: the last
	# frame's file was written at that tick (its mtime; the frame sleeps
	# until the tick, then renders and writes: at most 3 ticks, 1.5 s,
	# later under load), modulo the period (20 s: 40 ticks).  The last, not
	# the first: the world's first frame generates its whole view (2.5 s
	# under the suite's load, seen), the later ones a frame's work.
	last=$(ls -t "$name" | sed -n 's/^a\([0-9]*\)\.png$/\1/p' | head -1)
	mt=$([ -n "$last" ] && stat -c '%.3Y' "$name/a$last.png" 2>/dev/null)
	want=$(echo "${mt:-0}" | awk '{ printf "%d", ($1 * 2) % 40 }')
	if [ -n "$last" ] && [ -n "$mt" ] && [ $(((want - last + 40) % 40)) -le 3 ]; then
		ok
	else
		bad "$name: last frame's tick ${last:-none}, its file written at tick $want (mtime ${mt:-none})"
	fi
}
clock_check clock-volume --size 96x72 --grid 48
clock_check clock-world --size 96x54 --scene world --fade-time 0 --gen-per-frame 10000 --view-distance 30
fi

# ---- refusals -----------------------------------------------------------------
SMALL="--size 64x48 --grid 16 --out out.png"
expect_fail "tile: 2,0 is not on a 2x1 wall" --wall 2x1 --tile 2,0 $SMALL
expect_fail "wall: '3' is not COLSxROWS" --wall 3 $SMALL
expect_fail "tile: '1' is not C,R" --wall 2x1 --tile 1 $SMALL
expect_fail "bezel: '-4' is not X or X,Y" --wall 2x1 --bezel -4 $SMALL
expect_fail "bezel_mm: needs panel_mm" --wall 2x1 --bezel-mm 5 $SMALL
expect_fail "governor: on a 2x2 wall every tile holds one quality" --wall 2x2 --governor on $SMALL
expect_fail "clock: 'utc' is not auto or realtime" --clock utc $SMALL
expect_fail "rotate: the V4L2 output" --rotate 90 --v4l2 /dev/video9 $SMALL

echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
