#!/bin/sh
# isoterra — georeferenced DEMs end to end: the default run of a GeoTIFF
# DEM (no flags) fills the frame with its relief and names the map (size,
# CRS, extent, elevations) in an info line; a route on it is put in its
# frame; vertical_exaggeration changes the picture; an RGB GeoTIFF is
# refused with one line, a non-zero exit and no output.  The rasters are
# written by test_dem --make (GDAL's C API).
BIN=${1:-${ISOTERRA_BIN:-./build/isoterra}}
DEM=${2:?test_dem}
IMGCMP=${3:?imgcmp}
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
MAX_MSG_LINES=1
NO_OUTPUT=out.png
. "$(dirname "$0")/cli_lib.sh"
cd "$T" || exit 1
"$DEM" --make "$T" || { echo "FAIL: test_dem --make" >&2; exit 1; }
SIZE="--size 160x120 --grid 64"

# the default run: the info line, the frame mostly terrain
if "$BIN" $SIZE --heightmap geo.tif --out out.png >out 2>err && [ -s out.png ]; then
	ok
	cp out.png geo.png
else
	bad "the default DEM run: $(cat err)"
fi
info=$(grep "geo.tif: 201x161 samples" err)
echo "$info"
for pat in "WGS 84, EPSG:4326, geographic" "on the east-north grid at lon 7.383[0-9]* lat 45.8329[0-9]*" \
	"m apart: [0-9.]+ x [0-9.]+ m, lon \[7.30[0-9]*, 7.46[0-9]*\] lat \[45.76[0-9]*, 45.90[0-9]*\]" \
	"elevation -[0-9.]+ \.\. 2[89][0-9][0-9][.0-9]* m"; do
	if echo "$info" | grep -Eq "$pat"; then ok; else bad "info line lacks '$pat': $info"; fi
done
share=$("$DEM" --ground-share geo.png)
echo "default run of a 201x161 DEM: terrain on $share of the frame"
if awk "BEGIN { exit !($share > 0.5) }"; then ok; else bad "terrain on only $share of the default frame"; fi

# the projected DEM too
if "$BIN" $SIZE --heightmap utm.tif --out out.png 2>err && grep -q "utm.tif: 181x151 samples (WGS 84 / UTM zone 33N, EPSG:32633, projected" err; then
	ok
	share=$("$DEM" --ground-share out.png)
	echo "default run of the UTM DEM: terrain on $share of the frame"
	if awk "BEGIN { exit !($share > 0.5) }"; then ok; else bad "UTM: terrain on only $share of the frame"; fi
else
	bad "the UTM DEM: $(cat err)"
fi

# vertical exaggeration: another picture
if "$BIN" $SIZE --heightmap geo.tif --vertical-exaggeration 2 --out ex.png 2>err && [ -s ex.png ] &&
	! "$IMGCMP" geo.png ex.png >/dev/null; then
	ok
else
	bad "vertical_exaggeration 2 drew the same picture: $(cat err)"
fi

# a route on the DEM: put on its frame (said), inside the volume (no warning)
for r in route.geojson route.gpx; do
	if "$BIN" $SIZE --heightmap geo.tif --curves $r --out out.png 2>err &&
		grep -q "$r: .*east-north-up plane of the heightmap's centre at lon 7.383" err && ! grep -q warning err; then
		ok
	else
		bad "route $r on the DEM: $(cat err)"
	fi
done

# refusals: one line, non-zero, nothing written
expect_fail "heightmap 'rgb.tif' is a picture .*not elevations" $SIZE --field heightmap --heightmap rgb.tif --out out.png
expect_fail "curves_crs 'EPSG:x'" $SIZE --curves route.geojson --curves-crs EPSG:x --out out.png

echo "dem_cli: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
