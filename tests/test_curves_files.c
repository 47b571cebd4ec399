/* isoterra — test_curves (test_curves.c), the inputs: GeoJSON / CSV
 * parsing (good files and malformed ones), sizes, geographic input, the
 * heightmap (16-bit PNG, GeoTIFF through GDAL when the build has it) on
 * the CPU. */
#include "curves_test.h"
#include "world.h"
#include "terrain.h"

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <string.h>
#include <unistd.h>

/* ---- input files ----------------------------------------------------------------------- */

static void expect_parse_error(bool csv, const char *text, const char *want)
{
	struct curve_set s;
	char err[512] = "";
	int rc = csv ? curves_parse_csv(text, strlen(text), "t.csv", &s, err, sizeof(err))
		     : curves_parse_geojson(text, strlen(text), "t.geojson", &s, err, sizeof(err));
	CHECK(rc < 0 && strstr(err, want), "malformed %s: want '%s' in '%s'", csv ? "CSV" : "GeoJSON", want, err);
	if (rc == 0)
		curve_set_free(&s);
}

void test_io(void)
{
	const char *geo = "{ \"type\": \"FeatureCollection\", \"crs\": { \"type\": \"name\", \"properties\": { \"name\": \"local\" } },\n"
			  "  \"features\": [\n"
			  "  { \"type\": \"Feature\", \"properties\": { \"kind\": \"river\", \"width\": 12.5, \"name\": \"x\" },\n"
			  "    \"geometry\": { \"type\": \"LineString\", \"coordinates\": [[0, 0, 1], [10, 5, 2.5e0], [20, 0, -3]] } },\n"
			  "  { \"type\": \"Feature\", \"properties\": null,\n"
			  "    \"geometry\": { \"type\": \"MultiLineString\", \"coordinates\": [ [[0,0,0],[1,1,1]], [[5,5,5],[6,6,6],[7,7,7]] ] } }\n"
			  "] }\n";
	struct curve_set s;
	char err[512] = "";
	int rc = curves_parse_geojson(geo, strlen(geo), "t.geojson", &s, err, sizeof(err));
	CHECK(rc == 0, "valid GeoJSON: %s", err);
	if (rc == 0) {
		CHECK(s.npaths == 3, "3 line strings, got %d", s.npaths);
		CHECK(s.paths[0].kind == CURVE_RIVER && s.paths[0].width == 12.5f && s.paths[0].falloff == 12.0f,
		      "river properties (defaults for the rest)");
		CHECK(s.paths[0].npts == 3 && s.paths[0].pts[3] == 10.0f && s.paths[0].pts[4] == 2.5f &&
			      s.paths[0].pts[5] == -5.0f,
		      "[east, north, up] -> (x, up, -north)");
		CHECK(s.paths[2].npts == 3 && s.paths[1].kind == CURVE_ROAD, "MultiLineString parts");
		curve_set_free(&s);
	}
	const char *csv = "# roads\npath,x,y,z,kind,width,falloff,inclination,smoothing\n"
			  "a,0,1,0,railway,3,2,0.5,0.25\na,10,1,0,,,,,\n\n a , 20 , 2 , 5 ,,,,,\n"
			  "b,0,0,0,,,,,\nb,1,0,1,road,,,,\n";
	rc = curves_parse_csv(csv, strlen(csv), "t.csv", &s, err, sizeof(err));
	CHECK(rc == 0, "valid CSV: %s", err);
	if (rc == 0) {
		CHECK(s.npaths == 2 && s.paths[0].npts == 3 && s.paths[1].npts == 2, "two paths (%d)", s.npaths);
		CHECK(s.paths[0].kind == CURVE_RAILWAY && s.paths[0].width == 3.0f && s.paths[0].smoothing == 0.25f &&
			      s.paths[0].pts[7] == 2.0f,
		      "CSV values");
		curve_set_free(&s);
	}
	/* malformed: each names the line */
	expect_parse_error(false, "{ \"type\": \"FeatureCollection\", \"features\": [\n  { \"type\": \"Feature\",\n", "t.geojson:3");
	expect_parse_error(false, "{\n \"type\": \"Feature\", \"geometry\": { \"type\": \"LineString\",\n \"coordinates\": [[0,0,0,0],[1,1,1,1]] } }",
			   "t.geojson:3: feature 1: position 1 has 4 coordinates; GeoJSON positions are [x east, y north] "
			   "(the curve follows the ground) or [x east, y north, z up] (z up, unlike the CSV's y up)");
	expect_parse_error(false, "{\"type\":\"LineString\",\"coordinates\":[[0,0],[1,1,1]]}",
			   "position 2 has 3 coordinates, position 1 has 2: a line string is all 2D [x east, y north] or all "
			   "3D [x east, y north, z up]");
	expect_parse_error(false, "{\"type\":\"LineString\",\"coordinates\":[[0,0],[1,\"n\"]]}",
			   "position 2: y (north) is not a number");
	expect_parse_error(false, "{\"type\":\"LineString\",\"crs\":{\"type\":\"EPSG\"},\"coordinates\":[[0,0],[1,1]]}",
			   "\"crs\" must be");
	expect_parse_error(false, "{\"type\":\"Feature\",\"properties\":{\"width\":-3},\"geometry\":{\"type\":\"LineString\",\"coordinates\":[[0,0,0],[1,1,1]]}}",
			   "\"width\" = -3 must be");
	expect_parse_error(false, "{\"type\":\"Feature\",\"properties\":{\"kind\":\"canal\"},\"geometry\":{\"type\":\"LineString\",\"coordinates\":[[0,0,0],[1,1,1]]}}",
			   "\"kind\" must be");
	expect_parse_error(false, "{\"type\":\"Feature\",\"geometry\":{\"type\":\"LineString\",\"coordinates\":[[0,0,0],[0,0,0]]}}",
			   "2 distinct positions");
	expect_parse_error(false, "{\"type\":\"Feature\",\"geometry\":{\"type\":\"LineString\",\"coordinates\":[[0,0,0],[1,1,1],]}}",
			   "trailing comma");
	expect_parse_error(false, "{\"type\":\"Feature\",\"geometry\":{\"type\":\"LineString\",\"coordinates\":[[0,0,0],[1,1,01]]}}",
			   "expected ',' or ']'");
	expect_parse_error(false, "[1, 2]", "top level");
	expect_parse_error(false, "", "t.geojson:1: invalid JSON");
	expect_parse_error(false, "{\"type\":\"Feature\",\"geometry\":null}",
			   "t.geojson:1: GeoJSON: no line strings or polygons to carve (skipped: feature 1 without geometry (null))");
	expect_parse_error(false, "{\"type\":\"Feature\",\"geometry\":5}", "\"geometry\" must be a geometry object or null");
	expect_parse_error(false, "{\"type\":\"Circle\"}", "type \"Circle\" is not GeoJSON");
	expect_parse_error(false, "{\"type\":\"Feature\",\"bbox\":[0,0,1],\"geometry\":{\"type\":\"LineString\","
			   "\"coordinates\":[[0,0,0],[1,1,1]]}}", "t.geojson:1: feature 1: \"bbox\" must be [west, south, east, north]");
	expect_parse_error(false, "{\"type\":\"LineString\",\"bbox\":[0,5,1,2],\"coordinates\":[[0,0,0],[1,1,1]]}",
			   "geometry: \"bbox\": its south 5 is above its north 2");
	expect_parse_error(true, "path,x,y\na,0,0\n", "t.csv:1: the header has no 'z' column");
	expect_parse_error(true, "path,x,y,z\na,0,0,0\na,1,zz,0\n", "t.csv:3: y 'zz' is not a number");
	expect_parse_error(true, "path,x,y,z\na,0,0,0\na,1,0\n", "t.csv:3: 3 fields, the header has 4");
	expect_parse_error(true, "path,x,y,z\na,0,0,0\na,1,0,0\nb,0,0,0\nb,1,1,1\na,5,5,5\na,6,6,6\n", "t.csv:6: rows of path 'a'");
	expect_parse_error(true, "path,x,y,z,width\na,0,0,0,3\na,1,0,0,4\n", "t.csv:3: width of path 'a' changes");
	expect_parse_error(true, "path,x,y,z,smoothing\na,0,0,0,2\na,1,0,0,\n", "t.csv:2: smoothing = 2 must be in [0, 1]");
	expect_parse_error(true, "path,x,y,z\na,0,0,0\nb,0,0,0\nb,1,1,1\n", "t.csv:2: path 'a' needs at least 2");
	expect_parse_error(true, "path,x,y,z,colour\n", "unknown column 'colour'");
	expect_parse_error(true, "# nothing\n", "empty CSV");

	/* files: extension, missing file */
	CHECK(curves_load("/nonexistent/x.geojson", &s, err, sizeof(err)) < 0 && strstr(err, "cannot open"), "missing: %s",
	      err);
	CHECK(curves_load("roads.kml", &s, err, sizeof(err)) < 0 && strstr(err, "unknown format"), "kml: %s", err);
}

/* Notes of a set that hold `want` (all notes when want is NULL). */
static int notes_with(const struct curve_set *s, const char *want)
{
	int n = 0;
	for (int i = 0; i < s->nnotes; i++)
		n += !want || strstr(s->notes[i], want) != NULL;
	return n;
}

/* A file is never refused for one feature: a Point, a Polygon (areas are
 * not carved), a GeometryCollection, a null geometry are skipped, one
 * note per reason naming them; the line strings load.  bbox members are
 * checked, one note when the positions lie outside the top level's. */
void test_geojson_skips(void)
{
	const char *mix = "{ \"type\": \"FeatureCollection\", \"features\": [\n"
			  " { \"type\": \"Feature\", \"properties\": { \"width\": 4 }, \"geometry\": { \"type\": \"LineString\",\n"
			  "   \"coordinates\": [[-14, 9, 1], [0, -1, 1], [14, -9, 2]] } },\n"
			  " { \"type\": \"Feature\", \"id\": 7, \"geometry\": { \"type\": \"Polygon\", \"coordinates\":\n"
			  "   [[[0,0],[1,0],[1,1],[0,0]], [[0.2,0.2],[0.3,0.2],[0.3,0.3],[0.2,0.2]]] } },\n"
			  " { \"type\": \"Feature\", \"id\": \"node/5\", \"geometry\": { \"type\": \"Point\", \"coordinates\": [3, 3] } },\n"
			  " { \"type\": \"Feature\", \"geometry\": { \"type\": \"MultiLineString\",\n"
			  "   \"coordinates\": [[[-14, -9, 1], [14, 9, 1]], [[0, 0, 3], [5, 0, 3], [5, 5, 4]]] } }\n"
			  "] }\n";
	struct curve_set s;
	char err[512] = "";
	int rc = curves_parse_geojson(mix, strlen(mix), "mix.geojson", &s, err, sizeof(err));
	CHECK(rc == 0, "a Polygon and a Point among line strings: loaded (%s)", err);
	if (rc == 0) {
		/* the line, the polygon's outer ring and its hole, the two lines */
		CHECK(s.npaths == 5 && s.paths[0].npts == 3 && !s.paths[0].area && s.paths[1].area == AREA_FLAT &&
		      s.paths[1].ring == 0 && s.paths[2].area == AREA_FLAT && s.paths[2].ring == 1 && s.paths[3].npts == 2 &&
		      s.paths[4].npts == 3 && !s.paths[4].area,
		      "3 line strings and the Polygon's 2 rings loaded (%d paths)", s.npaths);
		CHECK(s.nnotes == 1, "one note (the Point), got %d", s.nnotes);
		CHECK(notes_with(&s, "mix.geojson: 1 feature skipped, not carved (only lines and polygons are): "
				     "feature 3 (id \"node/5\") Point") == 1,
		      "the Point named once: %s", s.nnotes ? s.notes[0] : "none");
		curve_set_free(&s);
	}
	/* good input: no note */
	const char *good = "{\"type\":\"FeatureCollection\",\"bbox\":[-1,-1,2,2],\"features\":[{\"type\":\"Feature\","
			   "\"bbox\":[0,0,1,1],\"geometry\":{\"type\":\"LineString\",\"bbox\":[0,0,1,1],"
			   "\"coordinates\":[[0,0,1],[1,1,1]]}}]}";
	rc = curves_parse_geojson(good, strlen(good), "good.geojson", &s, err, sizeof(err));
	CHECK(rc == 0 && s.npaths == 1 && s.nnotes == 0, "bbox members that hold the data: no note (%s, %d notes)", err,
	      rc == 0 ? s.nnotes : -1);
	if (rc == 0)
		curve_set_free(&s);
	/* many skipped: the first four named, the rest counted; malformed areas
	 * are skipped too (they are not carved either way); a collection */
	const char *many = "{\"type\":\"FeatureCollection\",\"bbox\":[0,0,0.5,0.5],\"features\":["
			   "{\"type\":\"Feature\",\"geometry\":{\"type\":\"LineString\",\"coordinates\":[[0,0,1],[1,1,1]]}},"
			   "{\"type\":\"Feature\",\"geometry\":{\"type\":\"Point\",\"coordinates\":[0,0]}},"
			   "{\"type\":\"Feature\",\"geometry\":{\"type\":\"MultiPoint\",\"coordinates\":[[0,0]]}},"
			   "{\"type\":\"Feature\",\"geometry\":{\"type\":\"GeometryCollection\",\"geometries\":[]}},"
			   "{\"type\":\"Feature\",\"geometry\":null},"
			   "{\"type\":\"Feature\",\"geometry\":{\"type\":\"Point\",\"coordinates\":[1,1]}},"
			   "{\"type\":\"Feature\",\"geometry\":{\"type\":\"Polygon\",\"coordinates\":[[[0,0],[1,0],[1,1],[0,1]]]}},"
			   "{\"type\":\"Feature\",\"geometry\":{\"type\":\"MultiPolygon\",\"coordinates\":"
			   "[[[[0,0],[1,0],[1,1],[0,0]]],[[[2,2],[3,2],[3,3],[2,2]]]]}}]}";
	rc = curves_parse_geojson(many, strlen(many), "many.geojson", &s, err, sizeof(err));
	CHECK(rc == 0 && s.npaths == 3 && s.paths[1].area && s.paths[2].area && s.paths[2].ring == 0,
	      "one line and the MultiPolygon's two outer rings among skipped features (%s)", err);
	if (rc == 0) {
		CHECK(s.nnotes == 3, "three notes (bbox, other, malformed areas), got %d", s.nnotes);
		CHECK(notes_with(&s, "5 features skipped, not carved (only lines and polygons are): feature 2 "
				     "Point, feature 3 MultiPoint, feature 4 GeometryCollection, feature 5 without geometry "
				     "(null), and 1 more") == 1,
		      "five skipped, four named");
		CHECK(notes_with(&s, "1 feature skipped, malformed areas: feature 7 Polygon "
				     "(malformed: ring 1 is not closed (its last position is not its first))") == 1,
		      "areas: the malformed one says why");
		CHECK(notes_with(&s, "many.geojson:1: the \"bbox\" [0, 0, 0.5, 0.5] does not hold every position: they span "
				     "x [0, 3], y [0, 3]; the positions are used") == 1,
		      "bbox inconsistent with the positions: one note");
		for (int i = 0; i < s.nnotes; i++)
			printf("  note: %s\n", s.notes[i]);
		curve_set_free(&s);
	}
	/* nothing to carve: refused, naming what was skipped */
	expect_parse_error(false, "{\"type\":\"Point\",\"coordinates\":[0,0]}",
			   "t.geojson:1: GeoJSON: no line strings or polygons to carve (skipped: geometry Point)");
}

/* Widths from feature properties: an explicit width (a number, or OSM's
 * string of metres) beats lanes, lanes
 * beat the OSM highway class, the class beats the road_width default;
 * falloff likewise; other kinds keep their defaults; CSV cells are the
 * file's own. */
void test_road_widths(void)
{
	const char *geo =
		"{\"type\":\"FeatureCollection\",\"features\":[\n"
		"{\"type\":\"Feature\",\"properties\":{\"lanes\":4},\"geometry\":{\"type\":\"LineString\",\"coordinates\":[[0,0,1],[1,0,1]]}},\n"
		"{\"type\":\"Feature\",\"properties\":{\"lanes\":\"3\"},\"geometry\":{\"type\":\"LineString\",\"coordinates\":[[0,0,1],[1,0,1]]}},\n"
		"{\"type\":\"Feature\",\"properties\":{\"highway\":\"motorway\"},\"geometry\":{\"type\":\"LineString\",\"coordinates\":[[0,0,1],[1,0,1]]}},\n"
		"{\"type\":\"Feature\",\"properties\":{\"highway\":\"footway\"},\"geometry\":{\"type\":\"LineString\",\"coordinates\":[[0,0,1],[1,0,1]]}},\n"
		"{\"type\":\"Feature\",\"properties\":{\"tags\":{\"highway\":\"primary\"}},\"geometry\":{\"type\":\"LineString\",\"coordinates\":[[0,0,1],[1,0,1]]}},\n"
		"{\"type\":\"Feature\",\"properties\":{\"width\":5,\"highway\":\"motorway\",\"lanes\":6},\"geometry\":{\"type\":\"LineString\",\"coordinates\":[[0,0,1],[1,0,1]]}},\n"
		"{\"type\":\"Feature\",\"properties\":{\"lanes\":2,\"highway\":\"motorway\",\"falloff\":2},\"geometry\":{\"type\":\"LineString\",\"coordinates\":[[0,0,1],[1,0,1]]}},\n"
		"{\"type\":\"Feature\",\"properties\":null,\"geometry\":{\"type\":\"LineString\",\"coordinates\":[[0,0,1],[1,0,1]]}},\n"
		"{\"type\":\"Feature\",\"properties\":{\"kind\":\"river\"},\"geometry\":{\"type\":\"LineString\",\"coordinates\":[[0,0,1],[1,0,1]]}},\n"
		"{\"type\":\"Feature\",\"id\":\"way/9\",\"properties\":{\"highway\":\"proposed\"},\"geometry\":{\"type\":\"LineString\",\"coordinates\":[[0,0,1],[1,0,1]]}},\n"
		"{\"type\":\"Feature\",\"properties\":{\"width\":\"7.5\",\"highway\":\"motorway\"},\"geometry\":{\"type\":\"LineString\",\"coordinates\":[[0,0,1],[1,0,1]]}},\n"
		"{\"type\":\"Feature\",\"properties\":{\"width\":\"6 m\"},\"geometry\":{\"type\":\"LineString\",\"coordinates\":[[0,0,1],[1,0,1]]}}\n"
		"]}";
	/* road_width 10 (a lane 5), road_falloff 3 */
	static const float want_w[12] = { 20, 15, 30, 2.5f, 20, 5, 10, 10, 10, 10, 7.5f, 6 };
	static const float want_f[12] = { 3, 3, 3, 3, 3, 3, 2, 3, 12, 3, 3, 3 };
	struct curve_set s;
	char err[512] = "";
	int rc = curves_parse_geojson(geo, strlen(geo), "w.geojson", &s, err, sizeof(err));
	CHECK(rc == 0 && s.npaths == 12, "widths file: %s", err);
	if (rc == 0 && s.npaths == 12) {
		curves_road_widths(&s, 10.0f, 3.0f);
		int bad = 0;
		for (int i = 0; i < 12; i++) {
			bool ok = s.paths[i].width == want_w[i] && s.paths[i].falloff == want_f[i];
			if (!ok)
				printf("  feature %d: width %g falloff %g, want %g %g\n", i + 1, (double)s.paths[i].width,
				       (double)s.paths[i].falloff, (double)want_w[i], (double)want_f[i]);
			bad += !ok;
		}
		CHECK(bad == 0, "lanes, highway classes, explicit width first, road_width / road_falloff defaults: %d wrong",
		      bad);
		CHECK(s.nnotes == 1 && notes_with(&s, "w.geojson: 1 feature of a highway class without a known width, given "
						      "road_width: feature 10 (id \"way/9\") \"proposed\"") == 1,
		      "the unknown class noted once (%d notes)", s.nnotes);
		curve_set_free(&s);
	}
	expect_parse_error(false, "{\"type\":\"Feature\",\"properties\":{\"lanes\":\"two\"},\"geometry\":{\"type\":"
			   "\"LineString\",\"coordinates\":[[0,0,1],[1,0,1]]}}", "feature 1: \"lanes\" must be a whole number from 1 to 16");
	expect_parse_error(false, "{\"type\":\"Feature\",\"properties\":{\"lanes\":0},\"geometry\":{\"type\":"
			   "\"LineString\",\"coordinates\":[[0,0,1],[1,0,1]]}}", "\"lanes\" must be a whole number");
	/* OSM's width tag is a string of metres; other units are refused */
	expect_parse_error(false, "{\"type\":\"Feature\",\"properties\":{\"width\":\"7 ft\"},\"geometry\":{\"type\":"
			   "\"LineString\",\"coordinates\":[[0,0,1],[1,0,1]]}}", "\"width\" \"7 ft\" is not a width in metres");
	expect_parse_error(false, "{\"type\":\"Feature\",\"properties\":{\"highway\":3},\"geometry\":{\"type\":"
			   "\"LineString\",\"coordinates\":[[0,0,1],[1,0,1]]}}", "\"highway\" must be a string");
	/* CSV: a width cell is the file's own; a road without one gets road_width */
	const char *csv = "path,x,y,z,width\na,0,0,0,3\na,1,0,0,\nb,0,0,0,\nb,1,0,1,\n";
	rc = curves_parse_csv(csv, strlen(csv), "w.csv", &s, err, sizeof(err));
	CHECK(rc == 0 && s.npaths == 2, "CSV widths: %s", err);
	if (rc == 0 && s.npaths == 2) {
		curves_road_widths(&s, 10.0f, 3.0f);
		CHECK(s.paths[0].width == 3.0f && s.paths[1].width == 10.0f && s.paths[1].falloff == 3.0f,
		      "CSV: width cell 3 kept, empty -> road_width 10 (%g, %g)", (double)s.paths[0].width,
		      (double)s.paths[1].width);
		curve_set_free(&s);
	}
}

/* A valley: the ground 0 for |x| > 10, 10 deeper between (a cosine). */
static bool valley_ground(void *ctx, float x, float z, float *y)
{
	(void)ctx;
	(void)z;
	*y = fabsf(x) < 10.0f ? -5.0f - 5.0f * cosf(x * 3.14159265f / 10.0f) : 0.0f;
	return true;
}

/* OSM's bridge / tunnel / surface tags: a bridge=yes way is a deck, a
 * tunnel=yes way a bore, each straight from the ground at one end to the
 * ground at the other; surfaces from the surface tag, else the highway
 * class, else the kind.  A 3D road that runs high over the valley is cut
 * into road, bridge, road. */
void test_structures(void)
{
	const char *geo =
		"{\"type\":\"FeatureCollection\",\"features\":[\n"
		"{\"type\":\"Feature\",\"properties\":{\"highway\":\"primary\",\"bridge\":\"yes\"},\"geometry\":{\"type\":\"LineString\",\"coordinates\":[[-12,0],[0,0],[12,0]]}},\n"
		"{\"type\":\"Feature\",\"properties\":{\"tags\":{\"highway\":\"secondary\",\"tunnel\":\"yes\"}},\"geometry\":{\"type\":\"LineString\",\"coordinates\":[[-12,5],[12,5]]}},\n"
		"{\"type\":\"Feature\",\"properties\":{\"highway\":\"residential\",\"bridge\":\"no\",\"surface\":\"gravel\"},\"geometry\":{\"type\":\"LineString\",\"coordinates\":[[-12,9],[12,9]]}},\n"
		"{\"type\":\"Feature\",\"properties\":{\"highway\":\"track\"},\"geometry\":{\"type\":\"LineString\",\"coordinates\":[[-12,12],[12,12]]}},\n"
		"{\"type\":\"Feature\",\"properties\":{\"highway\":\"footway\",\"surface\":\"paving_stones\"},\"geometry\":{\"type\":\"LineString\",\"coordinates\":[[-12,14],[12,14]]}},\n"
		"{\"type\":\"Feature\",\"properties\":{\"kind\":\"river\",\"bridge\":\"yes\"},\"geometry\":{\"type\":\"LineString\",\"coordinates\":[[-12,16],[12,16]]}}\n"
		"]}";
	struct curve_set s;
	char err[512] = "";
	int rc = curves_parse_geojson(geo, strlen(geo), "osm.geojson", &s, err, sizeof(err));
	CHECK(rc == 0 && s.npaths == 6, "structures file: %s", err);
	if (rc == 0 && s.npaths == 6) {
		static const int kind[6] = { CURVE_BRIDGE, CURVE_TUNNEL, CURVE_ROAD, CURVE_ROAD, CURVE_ROAD, CURVE_RIVER };
		static const int surf[6] = { SURFACE_ASPHALT, SURFACE_ASPHALT, SURFACE_GRAVEL, SURFACE_GRAVEL,
					     SURFACE_ASPHALT, SURFACE_NONE };
		int bad = 0;
		for (int i = 0; i < 6; i++) {
			bool ok = s.paths[i].kind == kind[i] && s.paths[i].surface == surf[i];
			if (!ok)
				printf("  feature %d: kind %s surface %s, want %s %s\n", i + 1, curve_kind_names[s.paths[i].kind],
				       curve_surface_names[s.paths[i].surface], curve_kind_names[kind[i]],
				       curve_surface_names[surf[i]]);
			bad += !ok;
		}
		CHECK(bad == 0, "bridge/tunnel tags make decks and bores, an explicit kind wins; surfaces from the tag, "
		      "the class, the kind: %d wrong", bad);
		curves_road_widths(&s, 8.0f, 8.0f);
		CHECK(s.paths[0].width == 16.0f && s.paths[0].falloff == 2.0f,
		      "a primary bridge keeps its class's width (16), its falloff is the deck's thickness (2): %g %g",
		      (double)s.paths[0].width, (double)s.paths[0].falloff);
		CHECK(curves_follow_ground(&s, 2.0f, valley_ground, NULL, err, sizeof(err)) == 0, "follow: %s", err);
		/* the deck and the bore run straight at 0 (both ends on the rim);
		 * the road follows the valley's floor */
		int off = 0;
		for (int i = 0; i < 2; i++)
			for (int k = 0; k < s.paths[i].npts; k++)
				off += fabsf(s.paths[i].pts[3 * k + 1]) > 1e-5f;
		CHECK(off == 0, "bridge and tunnel straight between their ends: %d points off", off);
		float mid = 1.0f;
		for (int k = 0; k < s.paths[2].npts; k++)
			if (fabsf(s.paths[2].pts[3 * k]) < 0.5f)
				mid = s.paths[2].pts[3 * k + 1];
		CHECK(fabsf(mid + 10.0f) < 0.1f, "the road follows the ground into the valley: %g at x = 0", (double)mid);
		curve_set_free(&s);
	}
	/* CSV: a surface column (our names or OSM's values), per path */
	const char *sc = "path,x,y,z,surface\na,0,0,0,gravel\na,1,0,0,\nb,0,0,1,ground\nb,1,0,1,ground\nc,0,0,2,\nc,1,0,2,\n";
	rc = curves_parse_csv(sc, strlen(sc), "s.csv", &s, err, sizeof(err));
	CHECK(rc == 0 && s.npaths == 3 && s.paths[0].surface == SURFACE_GRAVEL && s.paths[1].surface == SURFACE_DIRT &&
	      s.paths[2].surface == SURFACE_ASPHALT, "CSV surfaces gravel, dirt (OSM ground), the road's asphalt (%s)", err);
	if (rc == 0)
		curve_set_free(&s);
	rc = curves_parse_csv("path,x,y,z,surface\na,0,0,0,lava\na,1,0,0,\n", 41, "s.csv", &s, err, sizeof(err));
	CHECK(rc < 0 && strstr(err, "s.csv:2: surface 'lava' is not asphalt"), "an unknown surface refused: %s", err);
	if (rc == 0)
		curve_set_free(&s);
	rc = curves_parse_csv("path,x,y,z,surface\na,0,0,0,gravel\na,1,0,0,dirt\n", 47, "s.csv", &s, err, sizeof(err));
	CHECK(rc < 0 && strstr(err, "surface of path 'a' changes along the path"), "a changing surface refused: %s", err);
	if (rc == 0)
		curve_set_free(&s);
	/* 3D: a road at 0 across the valley, 7 points: its middle three run
	 * 6.5 .. 10 above the floor, more than w/2 + falloff = 4 */
	const char *csv = "path,x,y,z,width,falloff\n"
			  "a,-16,0,0,4,2\na,-12,0,0,,\na,-4,0,0,,\na,0,0,0,,\na,4,0,0,,\na,12,0,0,,\na,16,0,0,,\n";
	rc = curves_parse_csv(csv, strlen(csv), "high.csv", &s, err, sizeof(err));
	CHECK(rc == 0 && s.npaths == 1, "3D file: %s", err);
	if (rc == 0 && s.npaths == 1) {
		CHECK(curves_follow_ground(&s, 2.0f, valley_ground, NULL, err, sizeof(err)) == 0, "3D split: %s", err);
		CHECK(s.npaths == 3 && s.paths[0].kind == CURVE_ROAD && s.paths[1].kind == CURVE_BRIDGE &&
		      s.paths[2].kind == CURVE_ROAD, "road, bridge, road (%d paths)", s.npaths);
		if (s.npaths == 3)
			CHECK(s.paths[0].npts == 2 && s.paths[1].npts == 5 && s.paths[2].npts == 2 &&
			      s.paths[1].pts[0] == -12.0f && s.paths[1].pts[12] == 12.0f && s.paths[1].width == 4.0f,
			      "the bridge spans x -12 .. 12, sharing its end points, width kept (%d %d %d points)",
			      s.paths[0].npts, s.paths[1].npts, s.paths[2].npts);
		CHECK(notes_with(&s, "high.csv: 1 3D path runs far above or below the ground: 1 bridge and 0 tunnel part made") ==
		      1, "the split noted");
		curve_set_free(&s);
	}
}

/* Work sized from the input and refused before it is done: a road a
 * million units wide over a 1024^2 hash (each piece in every cell), files
 * with more points than the tables hold; 200 000 paths read in linear time
 * (a repeated id still found). */
void test_sizes(void)
{
	char err[512] = "";
	float pts[200 * 3];
	for (int i = 0; i < 200; i++) {
		pts[3 * i] = 10.0f * (float)i;
		pts[3 * i + 1] = 0.0f;
		pts[3 * i + 2] = 3.0f * (float)(i % 7);
	}
	struct curve_path wp = make_path(200, pts, 1e6f, 2, 0, 0);
	struct curve_set ws = { .paths = &wp, .npaths = 1 };
	struct curve_quads q;
	struct curve_hash h;
	CHECK(curves_build(&ws, &q, err, sizeof(err)) == 0, "wide road: %s", err);
	CHECK(curve_hash_build(&q, 1024, &h, err, sizeof(err)) == -1 && strstr(err, "curve hash too large: 416"),
	      "wide road over 1024^2 cells refused: '%s'", err);
	curve_quads_free(&q);

	long n = CURVE_MAX_POINTS + 1;
	size_t cap = (size_t)n * 16 + 256, len = 0;
	char *text = malloc(cap);
	len += (size_t)snprintf(text, cap, "path,x,y,z\n");
	for (long i = 0; i < n; i++)
		len += (size_t)snprintf(text + len, cap - len, "%ld,0,0,%d\n", i / 2, (int)(i % 2));
	struct curve_set s;
	CHECK(curves_parse_csv(text, len, "big.csv", &s, err, sizeof(err)) == -1 && strstr(err, "big.csv: 2097152 points"),
	      "CSV with too many points: '%s'", err);
	len = (size_t)snprintf(text, cap, "{\"type\":\"LineString\",\"coordinates\":[");
	for (long i = 0; i < n; i++)
		len += (size_t)snprintf(text + len, cap - len, "%s[%d,0,0]", i ? "," : "", (int)(i % 2));
	len += (size_t)snprintf(text + len, cap - len, "]}");
	CHECK(curves_parse_geojson(text, len, "big.geojson", &s, err, sizeof(err)) == -1 &&
		      strstr(err, "big.geojson: 2097152 positions"),
	      "GeoJSON with too many positions: '%s'", err);

	int np = 200000;
	len = (size_t)snprintf(text, cap, "path,x,y,z\n");
	for (int i = 0; i < np; i++)
		len += (size_t)snprintf(text + len, cap - len, "p%d,%d,0,0\np%d,%d,0,1\n", i, i, i, i);
	int rc = curves_parse_csv(text, len, "many.csv", &s, err, sizeof(err));
	CHECK(rc == 0 && s.npaths == np, "200 000 paths: %s", err);
	if (rc == 0)
		curve_set_free(&s);
	len += (size_t)snprintf(text + len, cap - len, "p17,0,0,0\np17,1,0,0\n");
	CHECK(curves_parse_csv(text, len, "many.csv", &s, err, sizeof(err)) == -1 && strstr(err, "rows of path 'p17'"),
	      "a repeated id among 200 000: '%s'", err);
	free(text);
}

/* ---- geographic input ---------------------------------------------------------------------- */

static int parse_geo(const char *text, struct curve_set *s)
{
	char err[512] = "";
	int rc = curves_parse_geojson(text, strlen(text), "g.geojson", s, err, sizeof(err));
	CHECK(rc == 0, "GeoJSON: %s", err);
	return rc;
}

/* lon/lat or world units, per the rule */
static bool geo_mode(const char *text, int mode, const char **why)
{
	struct curve_set s;
	bool ll = false;
	double c[2];
	char err[256];
	if (parse_geo(text, &s) == 0) {
		CHECK(curves_geo_project(&s, mode, 1.0f, NULL, &ll, why, c, err, sizeof(err)) == 0, "project: %s", err);
		curve_set_free(&s);
	}
	return ll;
}

static bool ramp_ground(void *ctx, float x, float z, float *y)
{
	(void)ctx;
	*y = 0.5f * x - 0.25f * z + 3.0f;
	return true;
}

void test_geo(void)
{
	/* WGS84 (crs member): 0.01 degree of longitude and of latitude at 45 N.
	 * Expected lengths from the WGS84 radii of curvature at 45 degrees:
	 * N = 6388838.29 m, M = 6367381.82 m, so 0.01 degree east is
	 * N cos 45 * 0.01 pi/180 = 788.468 m, 0.01 north 1111.330 m.  The
	 * east-north-up frame at the centroid (lat 44.998) is exact: the two
	 * points 0.01 degree apart at lat 44.995 are N cos 44.995 * 0.01 pi/180
	 * = 788.52 m apart along their parallel (ENU east: 0.02 m more). */
	const char *ll = "{\"type\":\"Feature\",\"crs\":{\"type\":\"name\",\"properties\":{\"name\":"
			 "\"urn:ogc:def:crs:OGC:1.3:CRS84\"}},\"geometry\":{\"type\":\"LineString\","
			 "\"coordinates\":[[7.00,44.995],[7.01,44.995],[7.01,45.005]]}}";
	struct curve_set s;
	char err[512];
	if (parse_geo(ll, &s) == 0) {
		bool lonlat;
		const char *why;
		double c[2];
		CHECK(s.paths[0].follow_ground && s.paths[0].crs == CURVE_CRS_WGS84, "2D, WGS84 named");
		CHECK(curves_geo_project(&s, CURVES_CRS_AUTO, 1.0f, NULL, &lonlat, &why, c, err, sizeof(err)) == 0, "%s", err);
		const float *q = s.paths[0].pts;
		CHECK(lonlat && strstr(why, "crs"), "lon/lat from the crs member (%s)", why);
		CHECK_NEAR(c[0], (7.00 + 2 * 7.01) / 3, 1e-9, "centroid lon");
		CHECK_NEAR(c[1], (44.995 * 2 + 45.005) / 3, 1e-9, "centroid lat");
		CHECK_NEAR(q[3] - q[0], 788.52, 0.05, "0.01 degree east at 44.995 N in metres");
		CHECK_NEAR(-(q[8] - q[5]), 1111.330, 0.05, "0.01 degree north at 45 N in metres (world z = -north)");
		CHECK_NEAR((q[0] + q[3] + q[6]) / 3, 0.0, 0.05, "x centred on the centroid (the frame is not linear in lon)");
		CHECK_NEAR((q[2] + q[5] + q[8]) / 3, 0.0, 0.5, "z near the centroid (the projection is not linear in lat)");
		curve_set_free(&s);
	}
	/* the auto rule */
	const char *why = "";
	const char *small = "{\"type\":\"LineString\",\"coordinates\":[[-3.70,40.41,650],[-3.69,40.42,655]]}";
	const char *local = "{\"type\":\"LineString\",\"coordinates\":[[-14,-2,1],[4,9,2]]}";
	const char *named = "{\"type\":\"LineString\",\"crs\":{\"type\":\"name\",\"properties\":{\"name\":"
			    "\"EPSG:25830\"}},\"coordinates\":[[0.1,0.2,0],[0.3,0.4,0]]}";
	CHECK(geo_mode(small, CURVES_CRS_AUTO, &why), "small lon/lat extent, no crs: lon/lat (%s)", why);
	CHECK(geo_mode(local, CURVES_CRS_AUTO, &why), "within lon/lat ranges over more than a degree: lon/lat (%s)", why);
	const char *beyond = "{\"type\":\"LineString\",\"coordinates\":[[-14,-2,1],[400,9,2]]}";
	CHECK(!geo_mode(beyond, CURVES_CRS_AUTO, &why), "beyond lon/lat ranges: world units (%s)", why);
	/* the span over a degree is said, once, and only when the rule decided */
	struct { const char *text; int mode; int notes; } spans[] = {
		{ local, CURVES_CRS_AUTO, 1 }, { local, CURVES_CRS_LOCAL, 0 }, { local, CURVES_CRS_LONLAT, 0 },
		{ small, CURVES_CRS_AUTO, 0 }, { beyond, CURVES_CRS_AUTO, 0 }, { ll, CURVES_CRS_AUTO, 0 },
	};
	for (size_t i = 0; i < sizeof(spans) / sizeof(spans[0]); i++) {
		if (parse_geo(spans[i].text, &s) != 0)
			continue;
		bool lonlat;
		double c[2];
		CHECK(curves_geo_project(&s, spans[i].mode, 1.0f, NULL, &lonlat, &why, c, err, sizeof(err)) == 0, "%s", err);
		CHECK(s.nnotes == spans[i].notes, "span note %zu: %d notes, want %d", i, s.nnotes, spans[i].notes);
		if (spans[i].notes)
			CHECK(notes_with(&s, "g.geojson: no crs member and every position within lon/lat ranges, spanning 18 "
					     "degrees of longitude and 11 of latitude: taken as WGS84 lon/lat") == 1,
			      "the span named: %s", s.nnotes ? s.notes[0] : "none");
		curve_set_free(&s);
	}
	CHECK(!geo_mode(named, CURVES_CRS_AUTO, &why), "another crs named: world units (%s)", why);
	CHECK(geo_mode(local, CURVES_CRS_LONLAT, &why), "forced lon/lat");
	CHECK(!geo_mode(small, CURVES_CRS_LOCAL, &why), "forced local");
	/* 3D lon/lat: the altitude scaled with the rest */
	if (parse_geo(small, &s) == 0) {
		bool lonlat;
		double c[2];
		CHECK(curves_geo_project(&s, CURVES_CRS_AUTO, 0.01f, NULL, &lonlat, &why, c, err, sizeof(err)) == 0, "%s", err);
		CHECK(!s.paths[0].follow_ground && fabsf(s.paths[0].pts[1] - 6.5f) < 1e-4f, "altitude 650 m at 0.01: y 6.5");
		curve_set_free(&s);
	}
	/* 2D: points every step along the line, each on the ground */
	const char *flat = "{\"type\":\"LineString\",\"coordinates\":[[-10,0],[10,0],[10,-5]]}";
	if (parse_geo(flat, &s) == 0) {
		CHECK(curves_follow_ground(&s, 2.0f, ramp_ground, NULL, err, sizeof(err)) == 0, "follow: %s", err);
		const struct curve_path *p = &s.paths[0];
		int bad = 0;
		for (int k = 0; k < p->npts; k++)
			bad += fabsf(p->pts[3 * k + 1] - (0.5f * p->pts[3 * k] - 0.25f * p->pts[3 * k + 2] + 3.0f)) > 1e-5f;
		CHECK(p->npts == 1 + 10 + 3, "20 + 5 units at most 2 apart: 14 points, got %d", p->npts);
		CHECK(bad == 0, "%d points off the ground", bad);
		curve_set_free(&s);
	}
	if (parse_geo(flat, &s) == 0) {
		CHECK(curves_follow_ground(&s, 2.0f, NULL, NULL, err, sizeof(err)) < 0 && strstr(err, "[x east, y north, z up]"),
		      "no ground to follow: %s", err);
		curve_set_free(&s);
	}
}

/* GPX: a track and the same line as GeoJSON lon/lat give the same
 * points, both at the lengths the WGS84 radii give (test_geo); routes,
 * several segments, points without <ele> (the ground); bad files refused
 * with file:line. */
static void expect_gpx_error(const char *text, const char *want)
{
	struct curve_set s;
	char err[512] = "";
	int rc = curves_parse_gpx(text, strlen(text), "t.gpx", &s, err, sizeof(err));
	CHECK(rc < 0 && s.npaths == 0 && strstr(err, want), "bad GPX: want '%s' in '%s'", want, err);
	if (rc == 0)
		curve_set_free(&s);
}

void test_gpx(void)
{
	const char *gpx = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
			  "<gpx version=\"1.1\" creator=\"t\" xmlns=\"http://www.topografix.com/GPX/1/1\"\n"
			  "     xmlns:x=\"http://example.com/ext\">\n"
			  " <trk><name>ridge</name><trkseg>\n"
			  "  <trkpt lat=\"44.995\" lon=\"7.00\"><ele>650</ele><extensions><x:ele>9</x:ele></extensions></trkpt>\n"
			  "  <trkpt lat=\"44.995\" lon=\"7.01\"><ele>660.5</ele></trkpt>\n"
			  "  <trkpt lat=\"45.005\" lon=\"7.01\"><ele>655</ele></trkpt>\n"
			  " </trkseg></trk>\n"
			  "</gpx>\n";
	const char *geo = "{\"type\":\"LineString\",\"coordinates\":[[7.00,44.995,650],[7.01,44.995,660.5],[7.01,45.005,655]]}";
	struct curve_set a, b;
	char err[512] = "";
	int ra = curves_parse_gpx(gpx, strlen(gpx), "t.gpx", &a, err, sizeof(err));
	CHECK(ra == 0, "GPX track: %s", err);
	int rb = curves_parse_geojson(geo, strlen(geo), "t.geojson", &b, err, sizeof(err));
	CHECK(rb == 0, "GeoJSON: %s", err);
	if (ra == 0 && rb == 0) {
		bool lla, llb;
		const char *why;
		double ca[2], cb[2];
		CHECK(a.npaths == 1 && a.paths[0].npts == 3 && !a.paths[0].follow_ground && a.nnotes == 0,
		      "one 3D path, no note");
		CHECK(strstr(a.paths[0].label, "t.gpx: track 1 \"ridge\", segment 1") != NULL, "label: %s", a.paths[0].label);
		CHECK(curves_geo_project(&a, CURVES_CRS_AUTO, 1.0f, NULL, &lla, &why, ca, err, sizeof(err)) == 0, "%s", err);
		CHECK(curves_geo_project(&b, CURVES_CRS_AUTO, 1.0f, NULL, &llb, &why, cb, err, sizeof(err)) == 0, "%s", err);
		CHECK(lla && llb, "both lon/lat");
		double worst = 0.0;
		for (int k = 0; k < 9; k++)
			worst = fmax(worst, fabs((double)a.paths[0].pts[k] - (double)b.paths[0].pts[k]));
		CHECK(worst < 1e-3, "GPX track == GeoJSON line string: worst difference %g m", worst);
		const float *q = a.paths[0].pts;
		CHECK_NEAR(q[3] - q[0], 788.52, 0.05, "GPX: 0.01 degree east at 44.995 N in metres");
		CHECK_NEAR(-(q[8] - q[5]), 1111.330, 0.05, "GPX: 0.01 degree north at 45 N in metres");
		CHECK_NEAR(q[4], 660.5, 1e-4, "GPX: <ele> is the height (not the extension's)");
	}
	if (ra == 0)
		curve_set_free(&a);
	if (rb == 0)
		curve_set_free(&b);
	/* a route, two segments of a track (one without <ele>: it follows the
	 * ground), a one-point segment and a waypoint skipped with notes; GPX
	 * 1.0 and no namespace read the same */
	const char *more = "<gpx version=\"1.0\" xmlns=\"http://www.topografix.com/GPX/1/0\">\n"
			   "<wpt lat=\"1\" lon=\"1\"/>\n"
			   "<rte><rtept lat=\"10\" lon=\"20\"><ele>1</ele></rtept><rtept lat=\"10.001\" lon=\"20\"><ele>2</ele></rtept>"
			   "<name>r</name></rte>\n"
			   "<trk><trkseg><trkpt lat=\"10\" lon=\"20.001\"/><trkpt lat=\"10.001\" lon=\"20.001\"/></trkseg>\n"
			   "<trkseg><trkpt lat=\"10\" lon=\"20.002\"/></trkseg></trk>\n"
			   "</gpx>";
	ra = curves_parse_gpx(more, strlen(more), "m.gpx", &a, err, sizeof(err));
	CHECK(ra == 0, "GPX route and track: %s", err);
	if (ra == 0) {
		CHECK(a.npaths == 2 && !a.paths[0].follow_ground && a.paths[1].follow_ground, "route 3D, track 2D (%d paths)",
		      a.npaths);
		CHECK(a.npaths == 2 && strstr(a.paths[0].label, "route 1 \"r\"") && strstr(a.paths[1].label, "track 1, segment 1"),
		      "labels");
		CHECK(a.nnotes == 2 && notes_with(&a, "m.gpx: 1 track segment or route of fewer than 2 distinct points skipped, "
						      "the first track 1, segment 2 (line 5)") == 1 &&
			      notes_with(&a, "m.gpx: 1 waypoint (<wpt>) skipped: points are not carved") == 1,
		      "notes: the short segment and the waypoint (%d)", a.nnotes);
		curve_set_free(&a);
	}
	/* bad files: file:line and what */
	expect_gpx_error("<gpx><trk><trkseg>\n<trkpt lat=\"1\" lon=\"2\">\n</trkseg></trk></gpx>",
			 "t.gpx:3: invalid XML: mismatched tag");
	expect_gpx_error("<gpx><trk><trkseg>\n<trkpt lat=\"1\" lon=\"2\"/>\n<trkpt lon=\"2\"/>\n</trkseg></trk></gpx>",
			 "t.gpx:3: <trkpt> has no lat attribute");
	expect_gpx_error("<gpx><rte>\n<rtept lat=\"1\"/></rte></gpx>", "t.gpx:2: <rtept> has no lon attribute");
	expect_gpx_error("<gpx><trk><trkseg>\n\n<trkpt lat=\"95\" lon=\"2\"/>\n</trkseg></trk></gpx>",
			 "t.gpx:3: <trkpt> lat=\"95\" is not a latitude in [-90, 90]");
	expect_gpx_error("<gpx><trk><trkseg><trkpt lat=\"1\" lon=\"200\"/></trkseg></trk></gpx>",
			 "t.gpx:1: <trkpt> lon=\"200\" is not a longitude in [-180, 180]");
	expect_gpx_error("<gpx><trk><trkseg><trkpt lat=\"1x\" lon=\"2\"/></trkseg></trk></gpx>", "lat=\"1x\" is not");
	expect_gpx_error("<gpx><trk><trkseg><trkpt lat=\"1\" lon=\"2\"><ele>high</ele></trkpt></trkseg></trk></gpx>",
			 "t.gpx:1: <ele>high</ele> is not a height");
	expect_gpx_error("<gpx><trk><trkpt lat=\"1\" lon=\"2\"/></trk></gpx>", "<trkpt> must be inside a <trkseg>");
	expect_gpx_error("<kml></kml>", "t.gpx:1: not GPX: the root element is <kml>");
	expect_gpx_error("<?xml version=\"1.0\"?>\n<!DOCTYPE gpx [<!ENTITY a \"aaaa\">]>\n<gpx/>", "t.gpx:2: a DTD");
	expect_gpx_error("<gpx><wpt lat=\"1\" lon=\"2\"/></gpx>",
			 "t.gpx: no track segment or route of 2 distinct points to carve (0 tracks, 0 routes, 1 waypoint)");
	expect_gpx_error("", "t.gpx:1: invalid XML: no element found");
}

/* 3D input whose every height is 0 is an export's placeholder: taken as
 * 2D (the ground), one note; a single non-zero height keeps it 3D. */
void test_flat_zero(void)
{
	const char *zero = "{\"type\":\"MultiLineString\",\"coordinates\":[[[0,0,0],[1,1,0]],[[2,2,0],[3,3,0],[4,3,0]]]}";
	const char *one = "{\"type\":\"MultiLineString\",\"coordinates\":[[[0,0,0],[1,1,0]],[[2,2,0],[3,3,0.5],[4,3,0]]]}";
	const char *gz = "<gpx><trk><trkseg><trkpt lat=\"1\" lon=\"2\"><ele>0</ele></trkpt><trkpt lat=\"1.001\" lon=\"2\">"
			 "<ele>0.0</ele></trkpt></trkseg></trk></gpx>";
	const char *g1 = "<gpx><trk><trkseg><trkpt lat=\"1\" lon=\"2\"><ele>0</ele></trkpt><trkpt lat=\"1.001\" lon=\"2\">"
			 "<ele>3</ele></trkpt></trkseg></trk></gpx>";
	struct curve_set s;
	char err[512] = "";
	if (parse_geo(zero, &s) == 0) {
		CHECK(s.npaths == 2 && s.paths[0].follow_ground && s.paths[1].follow_ground, "z = 0 everywhere: 2D");
		CHECK(s.nnotes == 1 && notes_with(&s, "g.geojson: the z (up) of all 5 3D positions is 0, which would carve at "
						      "height 0: taken as 2D, the curves follow the ground") == 1,
		      "one note: %s", s.nnotes ? s.notes[0] : "none");
		curve_set_free(&s);
	}
	if (parse_geo(one, &s) == 0) {
		CHECK(!s.paths[0].follow_ground && !s.paths[1].follow_ground && s.nnotes == 0, "one height 0.5: 3D, no note");
		curve_set_free(&s);
	}
	int rc = curves_parse_gpx(gz, strlen(gz), "z.gpx", &s, err, sizeof(err));
	CHECK(rc == 0, "GPX: %s", err);
	if (rc == 0) {
		CHECK(s.paths[0].follow_ground && s.nnotes == 1 &&
			      notes_with(&s, "z.gpx: the <ele> of all 2 3D positions is 0, which would carve at height 0") == 1,
		      "GPX <ele> 0 everywhere: 2D, one note");
		curve_set_free(&s);
	}
	rc = curves_parse_gpx(g1, strlen(g1), "z.gpx", &s, err, sizeof(err));
	CHECK(rc == 0 && !s.paths[0].follow_ground && s.nnotes == 0, "GPX with a height: 3D, no note (%s)", err);
	if (rc == 0)
		curve_set_free(&s);
}

/* The share of the curves' length inside a box (the volume's warning):
 * clipped exactly. */
void test_inside_fraction(void)
{
	float a[6] = { -10, 0, 0, 10, 0, 0 }, b[6] = { 20, 0, 20, 40, 0, 20 };
	struct curve_path pa = make_path(2, a, 1, 1, 0, 0), pb = make_path(2, b, 1, 1, 0, 0);
	struct curve_path both[2] = { pa, pb };
	struct curve_set s = { .paths = both, .npaths = 2 };
	float box[4] = { -5, -5, 5, 5 }, e[4];
	double f = curves_inside_fraction(&s, box, e);
	CHECK_NEAR(f, 10.0 / 40.0, 1e-9, "10 of 40 units inside");
	CHECK(e[0] == -10 && e[1] == 0 && e[2] == 40 && e[3] == 20, "extent x [-10, 40] z [0, 20]");
	float diag[6] = { -10, 0, -10, 10, 0, 10 };
	struct curve_path pd = make_path(2, diag, 1, 1, 0, 0);
	struct curve_set d = { .paths = &pd, .npaths = 1 };
	CHECK_NEAR(curves_inside_fraction(&d, box, e), 0.5, 1e-6, "a diagonal half inside");
}

/* A 2D GeoJSON file through the edit state and the terrain: every point on
 * the field's surface (CPU density: air just above, rock just below). */
void test_geo_terrain(void)
{
	char path[200], err[512] = "";
	snprintf(path, sizeof(path), "%.150s/flat.geojson", tmpdir);
	FILE *f = fopen(path, "w");
	CHECK(f != NULL, "write %s", path);
	if (!f)
		return;
	fputs("{\"type\":\"Feature\",\"properties\":{\"kind\":\"road\",\"width\":3},\"geometry\":{\"type\":"
	      "\"LineString\",\"coordinates\":[[-12,-9],[0,2],[13,6]]}}\n",
	      f);
	fclose(f);
	struct params p;
	params_defaults(&p);
	set(&p, "octaves=5;curves_crs=local");
	snprintf(p.curves, sizeof(p.curves), "%s", path);
	struct edits *ed = edits_create();
	struct terrain *tr = terrain_create(ed);
	CHECK(edits_load(ed, &p, err, sizeof(err)) == 0, "2D curves on the terrain: %s", err);
	static struct noise_set ns;
	noise_set_init(&ns, p.seed);
	int bad = 0, n = 0;
	if (ed->curves.npaths == 1) {
		const struct curve_path *c = &ed->curves.paths[0];
		for (int k = 0; k < c->npts; k++, n++) {
			const float *q = c->pts + 3 * k;
			bad += !(density_ref(&p, &ns, NULL, q[0], q[1] + 0.02f, q[2]) < p.iso &&
				 density_ref(&p, &ns, NULL, q[0], q[1] - 0.02f, q[2]) >= p.iso);
		}
	}
	CHECK(n > 10 && bad == 0, "2D curve on the surface: %d of %d points not", bad, n);
	terrain_destroy(tr);
	/* without a terrain there is no ground to follow: refused */
	edits_clear(ed);
	CHECK(edits_load(ed, &p, err, sizeof(err)) < 0 && strstr(err, "follow the terrain"), "no terrain: %s", err);
	edits_destroy(ed);
	unlink(path);
}

/* ---- heightmap (CPU) --------------------------------------------------------------------- */

static void hm_path(char *buf, size_t len, const char *name)
{
	snprintf(buf, len, "%s/%s", tmpdir, name);
}

#define HM_W 9
#define HM_H 7
static uint16_t hm_data[HM_W * HM_H];

#ifdef ISOTERRA_HAVE_GDAL
#include <gdal.h>
/* GeoTIFF through GDAL: a Float32 DEM in metres with a no-data sample is
 * read with its valid range [min, max] mapped onto 0..65535; garbage and a
 * band-less file are refused with a message naming the file. */
static void test_geotiff(void)
{
	char path[600], err[512];
	const int W = 7, H = 5;
	float dem[7 * 5];
	for (int z = 0; z < H; z++)
		for (int x = 0; x < W; x++)
			dem[z * W + x] = 250.0f + 3.5f * (float)x - 2.0f * (float)z; /* 242 .. 271 */
	dem[2 * W + 3] = -9999.0f;                                                  /* no data */
	GDALAllRegister();
	hm_path(path, sizeof(path), "dem.tif");
	GDALDriverH drv = GDALGetDriverByName("GTiff");
	CHECK(drv != NULL, "GDAL has the GTiff driver");
	if (!drv)
		return;
	GDALDatasetH ds = GDALCreate(drv, path, W, H, 1, GDT_Float32, NULL);
	CHECK(ds != NULL, "create %s", path);
	if (!ds)
		return;
	GDALRasterBandH b = GDALGetRasterBand(ds, 1);
	CHECK(GDALSetRasterNoDataValue(b, -9999.0) == CE_None, "set no-data");
	CHECK(GDALRasterIO(b, GF_Write, 0, 0, W, H, dem, W, H, GDT_Float32, 0, 0) == CE_None, "write GeoTIFF");
	GDALClose(ds);
	struct heightmap hm;
	CHECK(heightmap_load(path, &hm, err, sizeof(err)) == 0, "load GeoTIFF: %s", err);
	int bad = 0;
	for (int i = 0; i < W * H && hm.v; i++) {
		float want = i == 2 * W + 3 ? 0.0f : (dem[i] - 242.0f) / (271.0f - 242.0f) * 65535.0f;
		bad += fabsf(hm.v[i] - want) > 0.05f;
	}
	CHECK(hm.w == W && hm.h == H && bad == 0, "GeoTIFF %dx%d: %d samples differ from the normalised DEM", hm.w, hm.h,
	      bad);
	heightmap_free(&hm);
	hm_path(path, sizeof(path), "garbage.tif");
	FILE *f = fopen(path, "w");
	if (f) {
		fputs("II*\\0 this is not a TIFF", f);
		fclose(f);
	}
	CHECK(heightmap_load(path, &hm, err, sizeof(err)) < 0 && strstr(err, "garbage.tif") &&
		      strstr(err, "GDAL cannot read it"),
	      "garbage GeoTIFF refused by GDAL (through the module): %s", err);
	printf("  GeoTIFF through GDAL: %dx%d Float32 DEM with no-data read and normalised; garbage refused (%s)\n", W,
	       H, err);
}
#endif

void test_heightmap_cpu(struct edits *ed, struct params *p, const struct noise_set *ns)
{
	char path[256], err[512];
	for (int i = 0; i < HM_W * HM_H; i++)
		hm_data[i] = (uint16_t)(frand() * 65535.0f);
	hm_data[0] = 0;
	hm_data[1] = 65535;
	hm_path(path, sizeof(path), "hm.png");
	CHECK(image_write_png_gray16(path, hm_data, HM_W, HM_H, err, sizeof(err)) == 0, "write png16: %s", err);
	struct heightmap hm;
	CHECK(heightmap_load(path, &hm, err, sizeof(err)) == 0, "load: %s", err);
	int bad = 0;
	for (int i = 0; i < HM_W * HM_H && hm.v; i++)
		bad += hm.v[i] != (float)hm_data[i];
	CHECK(hm.w == HM_W && hm.h == HM_H && bad == 0, "16-bit round trip (%dx%d, %d differ)", hm.w, hm.h, bad);
	heightmap_free(&hm);
	CHECK(heightmap_load("x.tif", &hm, err, sizeof(err)) < 0 && strstr(err, "GDAL"), "GeoTIFF: %s", err);
#ifdef ISOTERRA_HAVE_GDAL
	test_geotiff();
#endif
	/* load through the parameters */
	char kv[512];
	snprintf(kv, sizeof(kv), "field=heightmap;heightmap=%s;heightmap_scale=2;heightmap_height=50;heightmap_base=-10;"
		 "heightmap_detail=0", path);
	set(p, kv);
	CHECK(edits_load(ed, p, err, sizeof(err)) == 0, "edits_load: %s", err);
	const struct edits *e = ed;
	/* exact at samples, with and without detail */
	p->heightmap_detail = 3.0f;
	double worst = 0;
	for (int z = 0; z < HM_H; z++)
		for (int x = 0; x < HM_W; x++) {
			float wx = ((float)x - 0.5f * (HM_W - 1)) * 2.0f, wz = ((float)z - 0.5f * (HM_H - 1)) * 2.0f;
			float want = -10.0f + (float)hm_data[z * HM_W + x] * 50.0f / 65535.0f;
			worst = fmax(worst, fabs(heightmap_ref_height(e, p, ns, wx, wz, true) - want));
		}
	CHECK(worst < 1e-4, "fractal interpolation exact at the samples (worst %g)", worst);
	/* between samples: detail adds roughness that bilinear lacks (magnified 16x) */
	double rough_b = 0, rough_f = 0, mean_dev = 0;
	int nline = 0;
	for (int z = 1; z < HM_H - 1; z++)
		for (int i = 1; i < 16 * (HM_W - 1) - 1; i++) {
			float wx0 = -0.5f * (HM_W - 1) * 2.0f;
			float wz = ((float)z - 0.5f * (HM_H - 1) + 0.37f) * 2.0f;
			float h3[2][3];
			for (int k = -1; k <= 1; k++) {
				float wx = wx0 + (float)(i + k) * 2.0f / 16.0f;
				h3[0][k + 1] = heightmap_ref_height(e, p, ns, wx, wz, false);
				h3[1][k + 1] = heightmap_ref_height(e, p, ns, wx, wz, true);
			}
			if ((i - 1) / 16 != (i + 1) / 16 || i % 16 == 0)
				continue; /* the stencil crosses a sample column: bilinear kinks there */
			rough_b += fabs(h3[0][0] - 2 * h3[0][1] + h3[0][2]);
			rough_f += fabs(h3[1][0] - 2 * h3[1][1] + h3[1][2]);
			mean_dev += fabs(h3[1][1] - h3[0][1]);
			nline++;
		}
	mean_dev /= nline;
	CHECK(rough_f > 3.0 * rough_b, "detail adds sub-sample roughness: %g vs bilinear %g", rough_f, rough_b);
	CHECK(mean_dev > 0.05 && mean_dev < 3.0, "detail deviation from bilinear %g (amplitude 3)", mean_dev);
	printf("  heightmap: roughness with detail %.3g vs bilinear %.3g, mean deviation %.3g\n", rough_f, rough_b,
	       mean_dev);
	/* bump continuity across a cell edge */
	float ex = (1.0f - 0.5f * (HM_W - 1)) * 2.0f, ez = (2.3f - 0.5f * (HM_H - 1)) * 2.0f;
	float l = heightmap_ref_height(e, p, ns, ex - 1e-3f, ez, true), r = heightmap_ref_height(e, p, ns, ex + 1e-3f, ez, true);
	CHECK(fabsf(l - r) < 0.05f, "continuous across a cell edge: %g vs %g", l, r);
}

/* Areas on a heightmap: a ramp (height x + 16 at x, one sample a unit);
 * a flat square is set to its rim's mean height, a pond to its rim's
 * lowest less 2 m (one lake at the rim's level), samples beyond the
 * falloff untouched; without the curves file the map's own samples are
 * back. */
void test_areas(void)
{
	enum { W = 33 };
	static uint16_t ramp[W * W];
	for (int j = 0; j < W; j++)
		for (int i = 0; i < W; i++)
			ramp[j * W + i] = (uint16_t)(i * 1000);
	char hm[256], geo[256], err[512] = "";
	hm_path(hm, sizeof(hm), "ramp.png");
	hm_path(geo, sizeof(geo), "areas.geojson");
	CHECK(image_write_png_gray16(hm, ramp, W, W, err, sizeof(err)) == 0, "write ramp: %s", err);
	FILE *f = fopen(geo, "w");
	CHECK(f != NULL, "write %s", geo);
	if (!f)
		return;
	fputs("{\"type\":\"FeatureCollection\",\"features\":[\n"
	      "{\"type\":\"Feature\",\"properties\":{\"leisure\":\"park\"},\"geometry\":{\"type\":\"Polygon\",\"coordinates\":"
	      "[[[-10,2],[-4,2],[-4,8],[-10,8],[-10,2]]]}},\n"
	      "{\"type\":\"Feature\",\"properties\":{\"natural\":\"water\"},\"geometry\":{\"type\":\"Polygon\",\"coordinates\":"
	      "[[[4,2],[10,2],[10,8],[4,8],[4,2]]]}}]}\n",
	      f);
	fclose(f);
	struct params p;
	params_defaults(&p);
	char kv[700];
	snprintf(kv, sizeof(kv), "field=heightmap;heightmap=%s;heightmap_scale=1;heightmap_base=0;heightmap_height=65.535;"
		 "heightmap_detail=0;heightmap_noise=0;curves=%s;curves_crs=local;road_falloff=2", hm, geo);
	set(&p, kv);
	struct edits *ed = edits_create();
	struct terrain *tr = terrain_create(ed);
	CHECK(edits_load(ed, &p, err, sizeof(err)) == 0, "areas on a heightmap: %s", err);
	CHECK(ed->curves.npaths == 0 && ed->areas.npaths == 2 && ed->nlakes == 1, "two areas, no curve, one lake (%d, %d, %d)",
	      ed->curves.npaths, ed->areas.npaths, ed->nlakes);
	float k = 65.535f / 65535.0f;
#define AT(x, z) (ed->hm.w == W ? ed->hm.v[((z) + 16) * W + (x) + 16] * k : NAN)
	/* the park: its rim runs x -10 .. -4 (ground 6 .. 12), mean 9 */
	int bad = 0;
	for (int z = -7; z <= -3; z++)
		for (int x = -9; x <= -5; x++)
			bad += fabsf(AT(x, z) - 9.0f) > 0.05f;
	CHECK(bad == 0, "the park flat at its rim's mean height 9: %d of 25 samples off (centre %g)", bad, AT(-7, -5));
	/* the pond: its rim's lowest ground is 20 (x = 4), the bed 2 below */
	bad = 0;
	for (int z = -7; z <= -3; z++)
		for (int x = 5; x <= 9; x++)
			bad += fabsf(AT(x, z) - 18.0f) > 0.05f;
	CHECK(bad == 0, "the pond's bed at 20 - 2: %d of 25 samples off (centre %g)", bad, AT(7, -5));
	if (ed->nlakes == 1)
		CHECK(fabsf(ed->lakes[0][4] - 20.0f) < 0.05f && fabsf(ed->lakes[0][0] - 4.0f) < 1e-4f &&
		      fabsf(ed->lakes[0][2] - 10.0f) < 1e-4f && fabsf(ed->lakes[0][1] + 8.0f) < 1e-4f &&
		      fabsf(ed->lakes[0][3] + 2.0f) < 1e-4f,
		      "the lake at 20 over x 4 .. 10, z -8 .. -2: %g over %g .. %g, %g .. %g", (double)ed->lakes[0][4],
		      (double)ed->lakes[0][0], (double)ed->lakes[0][2], (double)ed->lakes[0][1], (double)ed->lakes[0][3]);
	/* beyond the falloff (2): the ramp */
	bad = 0;
	for (int z = -16; z <= 16; z++)
		for (int x = -16; x <= 16; x++) {
			bool near = (z >= -11 && z <= 1) && ((x >= -13 && x <= -1) || (x >= 1 && x <= 13));
			bad += !near && fabsf(AT(x, z) - (float)(x + 16)) > 1e-3f;
		}
	CHECK(bad == 0, "samples beyond the areas' falloff untouched: %d differ", bad);
	/* no curves file: the ramp back, no lake */
	p.curves[0] = '\0';
	CHECK(edits_load(ed, &p, err, sizeof(err)) == 0, "areas dropped: %s", err);
	bad = 0;
	for (int z = -16; z <= 16; z++)
		for (int x = -16; x <= 16; x++)
			bad += fabsf(AT(x, z) - (float)(x + 16)) > 1e-3f;
	CHECK(bad == 0 && ed->nlakes == 0, "the map's own samples back: %d differ, %d lakes", bad, ed->nlakes);
#undef AT
	terrain_destroy(tr);
	edits_destroy(ed);
}
