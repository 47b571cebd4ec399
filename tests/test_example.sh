#!/bin/sh
# isoterra — roads that read as roads, and the worked example of real data:
#  1. the road surfaces in the shading: a primary road (asphalt), a track
#     (gravel) and a river (no surface) over the same heightmap, seen from
#     above: the asphalt darker than the bare ground of the river's run, the
#     gravel lighter, the ground away from the road unchanged;
#  2. docs/examples/goteborg (SRTM 3" DEM, OpenStreetMap roads: its
#     README.md) rendered with the command docs/CURVES.md gives, compared
#     with the stored picture docs/curves-goteborg.png, with no warning.
#     Needs the GeoTIFF module (GDAL): skipped, with the reason, in a build
#     without it.  The same files as a world: the first frame looks across
#     the map.
BIN=${1:-${ISOTERRA_BIN:-./build/isoterra}}
IMGCMP=${2:?imgcmp}
GDAL=${3:-yes}
SRC=${ISOTERRA_SRC:-$(cd "$(dirname "$0")/.." && pwd)}
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
. "$(dirname "$0")/cli_lib.sh"
cd "$T" || exit 1

# ---- 1. road surfaces -------------------------------------------------------
for s in asphalt gravel none; do
	case $s in
	asphalt) props='"highway": "primary", "width": 16' ;;
	gravel) props='"highway": "track", "width": 16' ;;
	none) props='"kind": "river", "width": 16' ;;
	esac
	cat >road_$s.geojson <<J
{ "type": "Feature", "properties": { $props },
  "geometry": { "type": "LineString", "coordinates": [[-60, 0], [60, 0]] } }
J
	if "$BIN" --size 320x240 --field heightmap --heightmap "$SRC/docs/examples/hill.png" --heightmap-scale 0.5 \
		--heightmap-base -12 --heightmap-height 32 --curves road_$s.geojson --curves-crs local --cam-yaw 35 --cam-pitch 89 \
		--cam-dist 1.2 --water false --out $s.png 2>err && [ -s $s.png ]; then
		ok
	else
		bad "the $s road: $(cat err)"
	fi
done
# the road runs through the picture's centre (the orbit's target), the
# grass at 20,130 is 40 units from it
lum() { "$IMGCMP" --info "$1" "$2" | awk '{ print 0.2126 * $3 + 0.7152 * $4 + 0.0722 * $5 }'; }
la=$(lum asphalt.png 150,110,20,20)
lg=$(lum gravel.png 150,110,20,20)
ln=$(lum none.png 150,110,20,20)
echo "road centre luminance: asphalt $la, gravel $lg, bare ground $ln"
if awk -v a="$la" -v g="$lg" -v n="$ln" 'BEGIN { exit !(a < n - 10 && g > n + 10) }'; then
	ok
else
	bad "asphalt ($la) should be darker than the bare ground ($ln) by 10, gravel ($lg) lighter by 10"
fi
if "$IMGCMP" asphalt.png none.png --region 10,125,40,30 --max-mean 0.5 >cmp; then
	ok
else
	bad "the ground 40 units from the road changed: $(cat cmp)"
fi

# ---- 2. the worked example ----------------------------------------------------
if [ "$GDAL" != yes ]; then
	echo "skip: the worked example reads a GeoTIFF DEM, and this build has no GeoTIFF module (no GDAL)"
else
	EX=$SRC/docs/examples/goteborg
	if ISOTERRA_MODULE_DIR=${ISOTERRA_MODULE_DIR:-${ISOTERRA_BUILD:-$SRC/build}} \
		"$BIN" --heightmap "$EX/dem.tif" --curves "$EX/roads.geojson" --vertical-exaggeration 3 \
		--curves-follow-step 8 --water-level 6 --grid 160 --size 640x360 --cam-yaw 200 --cam-pitch 35 \
		--cam-dist 1.1 --out goteborg.png 2>err && [ -s goteborg.png ]; then
		ok
	else
		bad "the worked example: $(cat err)"
	fi
	if grep -q "warning" err; then
		bad "the worked example warns: $(grep warning err)"
	else
		ok
	fi
	for pat in "dem.tif: 78x42 samples \(WGS 84, EPSG:4326, geographic" \
		"roads.geojson: WGS84 lon/lat .*east-north-up plane of the heightmap's centre" "road map: "; do
		if grep -Eq "$pat" err; then ok; else bad "no info line '$pat': $(cat err)"; fi
	done
	if "$IMGCMP" goteborg.png "$SRC/docs/curves-goteborg.png" --max-mean 2 --max-frac 0.02 >cmp; then
		ok
	else
		bad "the worked example differs from docs/curves-goteborg.png: $(cat cmp)"
	fi
	cat cmp
	# the world's start fitted to the map: the flight begins over its
	# western edge looking across it, so the lower half of the first frame
	# is the map (ground and river), darker than the sky above by far; an
	# unfitted start (--no-fit: blocks of 4, 60 units of view) looks over a
	# hazy plain (0.745 of the sky's luminance in this frame, 0.60 fitted)
	if ISOTERRA_MODULE_DIR=${ISOTERRA_MODULE_DIR:-${ISOTERRA_BUILD:-$SRC/build}} \
		"$BIN" --scene world --heightmap "$EX/dem.tif" --curves "$EX/roads.geojson" --vertical-exaggeration 3 \
		--curves-follow-step 8 --size 320x180 --count 1 --out world.png 2>err && [ -s world.png ] &&
		! grep -q warning err; then
		ok
	else
		bad "the worked example as a world: $(cat err)"
	fi
	lo=$(lum world.png 0,90,320,90)
	sky=$(lum world.png 0,0,320,30)
	echo "world's first frame: lower half luminance $lo, the sky band's $sky"
	if awk -v a="$lo" -v s="$sky" 'BEGIN { exit !(a < 0.7 * s) }'; then
		ok
	else
		bad "the world over the map starts looking at haze or sky: lower half $lo, sky $sky"
	fi
fi

echo "example: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
