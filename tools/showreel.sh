#!/bin/sh
# isoterra — the showreel: a fly-through of the streaming world across the
# landscape presets, each for an equal share of the time, crossfaded into
# the next (the attract playlist, --playlist), rendered offline (every frame,
# deterministic) to a Y4M file a kiosk or any player shows as it is
# (mpv, ffplay; `ffmpeg -i showreel.y4m showreel.mp4` to share it).
#
#   sh tools/showreel.sh [BIN [OUT]]     (defaults: ./build/isoterra, showreel.y4m)
#
# SHOWREEL_SECONDS (60), SHOWREEL_SIZE (1280x720), SHOWREEL_FPS (30),
# SHOWREEL_PRESETS (default canyon alien turbulence plains fbm).  The file is
# written whole or not at all (the program writes a temporary file and
# renames it).  2.49 GB at the defaults (1280x720 4:2:0, 1800 frames);
# about 7 minutes on a 2-core machine with llvmpipe (7:06 wall, 788 s of
# CPU, 2026-11-28), 219 MiB resident at the peak.  Each show is its preset's
# own flight from its spawn over its own terrain (the world is made again
# at each change).
set -eu
BIN=${1:-./build/isoterra}
OUT=${2:-showreel.y4m}
SECONDS_TOTAL=${SHOWREEL_SECONDS:-60}
SIZE=${SHOWREEL_SIZE:-1280x720}
FPS=${SHOWREEL_FPS:-30}
PRESETS=${SHOWREEL_PRESETS:-default canyon alien turbulence plains fbm}
n=0
for p in $PRESETS; do n=$((n + 1)); done
[ "$n" -gt 0 ] || { echo "showreel: SHOWREEL_PRESETS names no preset" >&2; exit 2; }
case $OUT in *.y4m) ;; *) echo "showreel: $OUT: the output must end in .y4m" >&2; exit 2 ;; esac
# each show's share in whole seconds (the last takes the rest); a crossfade
# of a second (a quarter of a show when shows are short)
share=$((SECONDS_TOTAL / n))
[ "$share" -ge 1 ] || { echo "showreel: $SECONDS_TOTAL s is too short for $n presets" >&2; exit 2; }
list= i=0 used=0
for p in $PRESETS; do
	i=$((i + 1))
	s=$share
	[ "$i" -lt "$n" ] || s=$((SECONDS_TOTAL - used))
	used=$((used + s))
	list="${list:+$list,}$p:$s"
done
fade=1
[ "$share" -ge 4 ] || fade=0.25
frames=$((SECONDS_TOTAL * FPS))
echo "showreel: $list, ${fade} s crossfades, $frames frames of $SIZE at $FPS fps -> $OUT"
exec "$BIN" --scene world --playlist "$list" --playlist-fade "$fade" --size "$SIZE" --fps "$FPS" \
	--count "$frames" --antialias msaa --out "$OUT"
