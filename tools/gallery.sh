#!/bin/sh
# isoterra — the gallery: every preset rendered, as the volume scene (the
# preset's own camera) and, for the terrain presets, as the streaming
# world's first frame (the autopilot's spawn view), into docs/gallery/, and
# a contact sheet of them all.
#
#   sh tools/gallery.sh [BIN [OUTDIR [IMGCMP]]]
#       (defaults: ./build/isoterra, docs/gallery, ./build/tests/imgcmp)
#
# Files: NAME.png (volume) and world-NAME.png (world), GALLERY_SIZE pixels
# (640x360), and contact-sheet.png (every picture at half size, a preset's
# two side by side, two presets a row).  README.md shows them (the
# no-flag picture on top, a table with a preset a row, the sheet).  The
# `gallery` test renders them again and compares them with the committed
# ones, so re-run this after any intended visual change.
set -eu
BIN=${1:-./build/isoterra}
OUT=${2:-docs/gallery}
IMGCMP=${3:-${IMGCMP:-./build/tests/imgcmp}}
SIZE=${GALLERY_SIZE:-640x360}
mkdir -p "$OUT"
# 4x multisampled whatever the driver (auto gives a software rasterizer
# the filter after the frame): the documentation's pictures get the best
# edges, and the same ones on every machine
render() { # the program's messages only when it fails
	"$BIN" --antialias msaa "$@" 2>"$OUT/.err.tmp" || { cat "$OUT/.err.tmp" >&2; rm -f "$OUT/.err.tmp"; exit 1; }
	rm -f "$OUT/.err.tmp"
}
"$BIN" --list-presets | awk 'NR > 1 { print $1 }' >"$OUT/.presets.tmp"
while read -r name; do
	render --preset "$name" --size "$SIZE" --out "$OUT/$name.png"
	# a world frame for the terrain presets (not the test fields, not the
	# diorama: the default's terrain, so the default's world frame)
	if [ "$name" != diorama ] && ! "$BIN" --list-presets | grep -q "^  $name  *test field"; then
		render --preset "$name" --scene world --size "$SIZE" --out "$OUT/world-$name.png"
	fi
	echo "$name"
done <"$OUT/.presets.tmp"
# the contact sheet, in the presets' order, a preset's volume and world
# pictures side by side
sheet=""
while read -r name; do
	sheet="$sheet $OUT/$name.png"
	[ ! -f "$OUT/world-$name.png" ] || sheet="$sheet $OUT/world-$name.png"
done <"$OUT/.presets.tmp"
rm -f "$OUT/.presets.tmp"
# shellcheck disable=SC2086 # a word list of paths without spaces
"$IMGCMP" --sheet "$OUT/contact-sheet.png" 4 $sheet
