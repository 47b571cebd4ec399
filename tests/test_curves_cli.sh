#!/bin/sh
# isoterra — curves and heightmaps end to end: good GeoJSON / CSV / PNG
# files render; malformed ones give one clear message naming the file, the
# line and the feature, a non-zero exit, and no output file.
BIN=${1:-${ISOTERRA_BIN:-./build/isoterra}}
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
MAX_MSG_LINES=2
NO_OUTPUT=out.png
. "$(dirname "$0")/cli_lib.sh"
SMALL="--size 64x48 --grid 16 --out out.png"

expect_ok() {
	rm -f out.png
	if "$BIN" "$@" >"$T/out" 2>"$T/err" && [ -s out.png ]; then
		ok
	else
		bad "isoterra $*: $(cat "$T/err")"
	fi
}

cd "$T" || exit 1

# ---- good files ---------------------------------------------------------------
cat >road.geojson <<'J'
{ "type": "FeatureCollection", "crs": { "type": "name", "properties": { "name": "local" } }, "features": [
  { "type": "Feature", "properties": { "kind": "road", "width": 4, "falloff": 3, "smoothing": 0.5 },
    "geometry": { "type": "LineString", "coordinates": [[-14, 9, 0], [0, -1, 1], [14, -9, 0]] } },
  { "type": "Feature", "properties": { "kind": "river", "width": 3, "falloff": 4 },
    "geometry": { "type": "MultiLineString", "coordinates": [[[-14, -12, -4], [14, 12, -5]]] } }
] }
J
cat >roads.csv <<'C'
path,x,y,z,kind,width,falloff,inclination,smoothing
r1,-14,0,-9,road,4,3,20,0.5
r1,0,1,0,,,,,
r1,14,0,9,,,,,
C
# a 6x5 16-bit grayscale PNG
echo 'iVBORw0KGgoAAAANSUhEUgAAAAYAAAAFEAAAAAATox55AAAATElEQVR4nAFBAL7/AAAAIyhGUGl4jKCvyAATiDawWdh9AKAow1AAJxBKOG1gkIizsNbYADqYXcCA6KQQxzjqYABOIHFIlHC3mNrA/egngBxszlxjvgAAAABJRU5ErkJggg==' | base64 -d >hm.png
expect_ok $SMALL --curves road.geojson
expect_ok $SMALL --curves roads.csv --curve-hash-dim 4
expect_ok $SMALL --field heightmap --heightmap hm.png --heightmap-scale 6 --heightmap-detail 1 --curves road.geojson
printf 'field = heightmap\nheightmap = hm.png\ncurves = roads.csv\nheightmap_scale = 6\n' >edit.conf
expect_ok $SMALL --config edit.conf
# the control map: a grayscale PNG; a missing or broken one is one message
expect_ok $SMALL --control-strength 0.8 --control-map hm.png
expect_fail "cannot open control map file 'nothere.png'" $SMALL --control-strength 0.8 --control-map nothere.png
echo 'not a png' >bad.png
expect_fail "control map: 'bad.png' is not a PNG file" $SMALL --control-strength 0.8 --control-map bad.png
# 2D positions follow the ground; WGS84 lon/lat (a small area) is projected
cat >flat.geojson <<'J'
{ "type": "LineString", "coordinates": [[-14, 9], [0, -1], [14, -9]] }
J
expect_ok $SMALL --curves flat.geojson --curves-crs local
expect_ok $SMALL --field heightmap --heightmap hm.png --heightmap-scale 6 --curves flat.geojson --curves-crs local
cat >lonlat.geojson <<'J'
{ "type": "Feature", "properties": { "kind": "road", "width": 4 },
  "geometry": { "type": "LineString", "coordinates": [[-3.70010, 40.41690], [-3.70000, 40.41700], [-3.69985, 40.41705]] } }
J
expect_ok $SMALL --curves lonlat.geojson

# a Polygon and a Point among line strings: the lines are carved, one
# warning each for the area (areas need a heightmap) and the point; a good
# file warns of nothing
cat >mix.geojson <<'J'
{ "type": "FeatureCollection", "features": [
  { "type": "Feature", "properties": { "width": 4 },
    "geometry": { "type": "LineString", "coordinates": [[-14, 9, 1], [0, -1, 1], [14, -9, 2]] } },
  { "type": "Feature", "id": "way/7", "geometry": { "type": "Polygon", "coordinates": [[[0, 0], [1, 0], [1, 1], [0, 0]]] } },
  { "type": "Feature", "geometry": { "type": "Point", "coordinates": [3, 3] } }
] }
J
# expect_warn "regex" COUNT args...: the run succeeds, COUNT stderr lines match
expect_warn() {
	pat=$1
	want=$2
	shift 2
	rm -f out.png
	if ! "$BIN" "$@" >"$T/out" 2>"$T/err" || [ ! -s out.png ]; then
		bad "isoterra $*: $(cat "$T/err")"
		return
	fi
	n=$(grep -Ec "$pat" "$T/err")
	if [ "$n" -ne "$want" ]; then
		bad "isoterra $*: $n lines match '$pat', want $want: $(cat "$T/err")"
		return
	fi
	ok
}
expect_warn "warning: mix.geojson: 1 area .1 ring. not carved: areas flatten or flood a heightmap .field = heightmap., and this field is terrain" 1 \
	$SMALL --curves mix.geojson --curves-crs local
expect_warn "warning: mix.geojson: 1 feature skipped, not carved .only lines and polygons are.: feature 3 Point" 1 \
	$SMALL --curves mix.geojson --curves-crs local
expect_warn "warning" 2 $SMALL --curves mix.geojson --curves-crs local
expect_warn "warning" 0 $SMALL --curves road.geojson

# ---- no silent no-ops: one warning each, naming the values; none on good input
# lon/lat-looking positions spanning 9 degrees without a crs member: lon/lat
# (RFC 7946), said; 1000 km lie outside the volume, said with both extents
cat >wide.geojson <<'J'
{ "type": "LineString", "coordinates": [[-3.0, 40.0, 600], [6.0, 40.5, 650]] }
J
expect_warn "warning: wide.geojson: no crs member and every position within lon/lat ranges, spanning 9 degrees of longitude and 0.5 of latitude: taken as WGS84 lon/lat" 1 \
	$SMALL --curves wide.geojson
# (the exact east-north-up frame bends a parallel 9 degrees long away from the volume: all of it, or nearly)
expect_warn "warning: wide.geojson: (over 99.9%|all) of the curves' length lies outside the volume: the curves span x \[-3[0-9.e+]*, 3[0-9.e+]*\] z \[-[0-9.e+]*, [0-9.e+]*\], the volume x \[-48, 48\] z \[-48, 48\]" 1 \
	$SMALL --curves wide.geojson
expect_warn "warning" 2 $SMALL --curves wide.geojson
expect_warn "warning" 1 $SMALL --curves wide.geojson --curves-crs lonlat
# a 3.4 km GPX route at 1 world unit a metre: mostly outside; scaled, inside
cat >route.gpx <<'X'
<gpx version="1.1" xmlns="http://www.topografix.com/GPX/1/1"><rte>
<rtept lat="40.400" lon="-3.700"><ele>4</ele></rtept><rtept lat="40.415" lon="-3.7003"><ele>5</ele></rtept>
<rtept lat="40.430" lon="-3.700"><ele>4</ele></rtept></rte></gpx>
X
expect_warn "warning: route.gpx: 97\.[0-9]% of the curves' length lies outside the volume: the curves span x \[-1[0-9.]*, [0-9.]*\] z \[-166[0-9.]*, 166[0-9.]*\], the volume x \[-48, 48\] z \[-48, 48\]" 1 \
	$SMALL --curves route.gpx
expect_warn "warning" 1 $SMALL --curves route.gpx
expect_warn "warning" 0 $SMALL --curves route.gpx --curves-geo-scale 0.025
# 3D positions whose every height is 0: taken as 2D on the ground
cat >zero.geojson <<'J'
{ "type": "LineString", "crs": { "type": "name", "properties": { "name": "local" } },
  "coordinates": [[-14, 9, 0], [0, -1, 0], [14, -9, 0]] }
J
expect_warn "warning: zero.geojson: the z .up. of all 3 3D positions is 0, which would carve at height 0: taken as 2D, the curves follow the ground" 1 \
	$SMALL --curves zero.geojson
expect_warn "warning" 1 $SMALL --curves zero.geojson
# --heightmap alone implies field = heightmap (a note); with another field
# given (an option, a preset) it is unused (a warning); with it, neither
expect_warn "info: heightmap hm.png given without a field: field = heightmap" 1 $SMALL --heightmap hm.png
expect_warn "warning" 0 $SMALL --heightmap hm.png
expect_warn "warning: heightmap hm.png is not used: field = torus .only field = heightmap reads it." 1 \
	$SMALL --heightmap hm.png --field torus
expect_warn "warning: heightmap hm.png is not used: field = torus" 1 $SMALL --preset torus --heightmap hm.png
expect_warn "heightmap hm.png" 0 $SMALL --heightmap hm.png --field heightmap
expect_warn "heightmap" 0 $SMALL --field terrain

# ---- malformed GeoJSON ------------------------------------------------------------
printf '{ "type": "FeatureCollection", "features": [\n  { "type": "Feature",\n' >trunc.geojson
expect_fail "trunc.geojson:3: invalid JSON" $SMALL --curves trunc.geojson
cat >twod.geojson <<'J'
{ "type": "FeatureCollection", "features": [
  { "type": "Feature", "geometry": { "type": "LineString", "coordinates": [[0, 0, 0], [1, 1, 1]] } },
  { "type": "Feature", "geometry": { "type": "LineString",
    "coordinates": [[0, 0, 0, 1], [5, 5, 0, 1]] } }
] }
J
expect_fail "twod.geojson:4: feature 2: position 1 has 4 coordinates; GeoJSON positions are .x east, y north. .the curve follows the ground. or .x east, y north, z up. .z up, unlike the CSV.s y up." $SMALL --curves twod.geojson
cat >poly.geojson <<'J'
{ "type": "Feature", "geometry": { "type": "Polygon", "coordinates": [] } }
J
expect_fail "poly.geojson:1: GeoJSON: no line strings or polygons to carve .skipped: feature 1 Polygon .malformed" $SMALL --curves poly.geojson
cat >width.geojson <<'J'
{ "type": "Feature",
  "properties": { "width": "wide" },
  "geometry": { "type": "LineString", "coordinates": [[0, 0, 0], [1, 1, 1]] } }
J
expect_fail "width.geojson:2: feature 1: \"width\" \"wide\" is not a width in metres" $SMALL --curves width.geojson
expect_fail "cannot open curves file" $SMALL --curves missing.geojson
expect_fail "unknown format" $SMALL --curves roads.kml

# road widths: --road-width sets a road's that the file leaves open (the
# picture changes), not one the file gives (the picture stays); a width
# out of range is refused
cat >open.geojson <<'J'
{ "type": "LineString", "coordinates": [[-14, 9, 3], [0, -1, 4], [14, -9, 3]] }
J
sed 's/"type": "LineString"/"type": "Feature", "properties": { "width": 4 }, "geometry": { "type": "LineString"/; s/]] }/]] } }/' \
	open.geojson >given.geojson
for f in open given; do
	for w in 2 30; do
		expect_ok $SMALL --curves-crs local --curves $f.geojson --road-width $w
		cp out.png "$f-$w.png"
	done
done
if cmp -s open-2.png open-30.png; then bad "--road-width 2 and 30 drew the same road"; else ok; fi
if cmp -s given-2.png given-30.png; then ok; else bad "--road-width changed a road whose width the file gives"; fi
expect_fail "road_width: 0 is out of range" $SMALL --curves open.geojson --road-width 0
expect_fail "road_falloff: -1 is out of range" $SMALL --curves open.geojson --road-falloff -1

# ---- GPX ------------------------------------------------------------------------------
cat >ride.gpx <<'X'
<?xml version="1.0" encoding="UTF-8"?>
<gpx version="1.1" creator="t" xmlns="http://www.topografix.com/GPX/1/1">
 <trk><name>ride</name><trkseg>
  <trkpt lat="40.41690" lon="-3.70010"><ele>4</ele></trkpt>
  <trkpt lat="40.41700" lon="-3.70000"><ele>5</ele></trkpt>
  <trkpt lat="40.41705" lon="-3.69985"><ele>4.5</ele></trkpt>
 </trkseg></trk>
</gpx>
X
expect_warn "warning" 0 $SMALL --curves ride.gpx
printf '<gpx><trk><trkseg>\n<trkpt lat="1" lon="2">\n</trkseg></trk></gpx>\n' >broken.gpx
expect_fail "^isoterra: error: broken.gpx:3: invalid XML: mismatched tag" $SMALL --curves broken.gpx
printf '<gpx><trk><trkseg>\n<trkpt lat="1" lon="2"/>\n<trkpt lon="2.001"/>\n</trkseg></trk></gpx>\n' >nolat.gpx
expect_fail "^isoterra: error: nolat.gpx:3: <trkpt> has no lat attribute" $SMALL --curves nolat.gpx
printf '<gpx><rte>\n<rtept lat="1" lon="2"/>\n<rtept lat="91" lon="2"/>\n</rte></gpx>\n' >lat.gpx
expect_fail "^isoterra: error: lat.gpx:3: <rtept> lat=.91. is not a latitude in \[-90, 90\]" $SMALL --curves lat.gpx

# ---- malformed CSV ------------------------------------------------------------------
printf 'path,x,y,z\na,0,0,0\na,1,oops,1\n' >bad.csv
expect_fail "bad.csv:3: y 'oops' is not a number" $SMALL --curves bad.csv
printf 'path,x,y,z,kind\na,0,0,0,canal\na,1,1,1,canal\n' >kind.csv
expect_fail "kind.csv:2: kind 'canal'" $SMALL --curves kind.csv
printf 'x,y,z\n0,0,0\n' >nohead.csv
expect_fail "nohead.csv:1: the header has no 'path' column" $SMALL --curves nohead.csv

# ---- malformed heightmaps -----------------------------------------------------------
echo "not a png" >text.png
expect_fail "text.png" $SMALL --field heightmap --heightmap text.png
head -c 60 hm.png >trunc.png
expect_fail "trunc.png" $SMALL --field heightmap --heightmap trunc.png
"$BIN" --size 16x16 --grid 4 --out rgb.png >/dev/null 2>&1 || bad "could not make an RGB PNG"
expect_fail "rgb.png.*grayscale" $SMALL --field heightmap --heightmap rgb.png
expect_fail "GDAL" $SMALL --field heightmap --heightmap dem.tif
# a GeoTIFF read through the module (isoterra-geotiff.so, next to the
# program or in $ISOTERRA_MODULE_DIR): GDAL's own refusal of a file that is
# not one; a copy of the program with no module anywhere names the module
# and where it looked (a build without GDAL says so instead)
printf 'II*\000 this is not a TIFF' >bad.tif
if "$BIN" --help 2>/dev/null | grep -q "GeoTIFF" && [ -e "$(dirname "$BIN")/isoterra-geotiff.so" ]; then
	expect_fail "bad.tif.*GDAL cannot read it as a GeoTIFF" $SMALL --field heightmap --heightmap bad.tif
	mkdir -p lone && cp "$BIN" lone/isoterra
	BIN0=$BIN
	BIN=$PWD/lone/isoterra
	ISOTERRA_MODULE_DIR= expect_fail "bad.tif.*need the module isoterra-geotiff.so.*not loaded from $PWD/lone" \
		$SMALL --field heightmap --heightmap bad.tif
	BIN=$BIN0
else
	expect_fail "bad.tif.*GDAL" $SMALL --field heightmap --heightmap bad.tif
fi
expect_fail "field=heightmap needs a heightmap" $SMALL --field heightmap
expect_fail "cannot open.*nothere.png" $SMALL --field heightmap --heightmap nothere.png

echo "curves_cli: $pass passed, $fail failed"
[ $fail -eq 0 ]
