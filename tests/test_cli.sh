#!/bin/sh
# isoterra — the program end to end: the default run writes a PNG, the mesh
# export writes a PLY, and bad input (CLI values, config, a broken shader)
# gives a non-zero exit and one clear message; a world flight in empty sky
# is said once.
BIN=${1:-${ISOTERRA_BIN:-./build/isoterra}}
SRC=${ISOTERRA_SRC:-$(dirname "$0")/..}
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
. "$(dirname "$0")/cli_lib.sh"

cd "$T" || exit 1
expect_fail "unknown option '--nope'" --nope
expect_fail "grid.*out of range" --grid 0
expect_fail "grid.*not an integer" --grid abc
expect_fail "grid.*needs a value|option '--grid'" --grid
expect_fail "size" --size 10x
expect_fail "size" --size 0x100
expect_fail "\.png" --out picture.jpg
expect_fail "\.ply" --export-mesh mesh.obj
expect_fail "unknown preset 'nope'" --preset nope
expect_fail "cannot open config file" --config /nonexistent/isoterra.conf
printf 'grid = 16\noctaves = many\n' >bad.conf
expect_fail "bad.conf:2" --config bad.conf
printf 'grid 16\n' >bad2.conf
expect_fail "bad2.conf:1" --config bad2.conf
expect_fail "noise.*not one of" --noise perlin2
expect_fail "unknown platform|platform" --platform nonsense --size 64x48 --grid 8
expect_fail "cannot open shader|shader" --shader-dir /nonexistent --size 64x48 --grid 8
# display platforms: clear errors without a display; a missing card is named
# before the EGL is asked for GBM (an EGL without EGL_KHR_platform_gbm, as
# NVIDIA's EGL device, still says which node is missing)
expect_fail "cannot open /nonexistent/card9|unknown platform 'gbm'" --platform gbm -D /nonexistent/card9 --size 64x48 --grid 8
expect_fail "cannot open /nonexistent/card9|unknown platform 'gbm'" --platform gbm --drm-device /nonexistent/card9 --size 64x48 --grid 8
expect_fail "option '-D' needs a value" -D
expect_fail "count 0.*needs a display platform" --platform surfaceless --count 0 --size 64x48 --grid 8
# --outputs: KMS connectors (gbm, or auto), a tile each along the wall's row
expect_fail "outputs: 'all' names KMS connectors, which --platform gbm \(or auto\) drives, not 'surfaceless'" --platform surfaceless --outputs all --size 64x48 --grid 8
expect_fail "outputs: 2 tile\(s\) along the row from tile 1,0 run past the 2x1 wall" --wall 2x1 --tile 1,0 --outputs HDMI-A-1,HDMI-A-2 --size 64x48 --grid 8
expect_fail "cannot open /nonexistent/card9|this build has no gbm platform" --outputs HDMI-A-1,HDMI-A-2 --wall 2x1 -D /nonexistent/card9 --size 64x48 --grid 8
# a broken shader: the message names file:line
mkdir shaders
cp "$SRC"/shaders/* shaders/
line=$(grep -n "^float density(vec3" shaders/density.glsl | head -1 | cut -d: -f1)
if [ -n "$line" ]; then
	sed -i "$((line + 2))s/^/\tthis is not glsl;\n/" shaders/density.glsl
	expect_fail "density.glsl:$((line + 2)):" --shader-dir shaders --size 64x48 --grid 8
else
	bad "density.glsl has no 'float density(vec3' line"
fi
# nothing half-written by the failures above
if ls | grep -Eq '\.png|\.ply'; then bad "failed runs left files: $(ls)"; else ok; fi

# --help and --list-presets exit 0
"$BIN" --help >help.txt 2>&1 && grep -q -- "--grid" help.txt && ok || bad "--help"
"$BIN" --list-presets >presets.txt 2>&1 && grep -q "canyon" presets.txt && ok || bad "--list-presets"

# a small real run: PNG + PLY, no temp files left
if "$BIN" --size 96x64 --grid 24 --out small.png --export-mesh small.ply >run.txt 2>&1; then
	ok
	head -c 8 small.png | od -An -tx1 | grep -q "89 50 4e 47 0d 0a 1a 0a" && ok || bad "small.png is not a PNG"
	head -c 64 small.ply | grep -q "binary_little_endian" && ok || bad "small.ply is not a binary PLY"
	[ "$(ls | grep -c '\.tmp\|XXXXXX\|small\.p.*\..')" -eq 0 ] && ok || bad "temp files left: $(ls)"
else
	bad "small run failed: $(cat run.txt)"
fi
# frame sequence
if "$BIN" --size 64x48 --grid 12 --count 3 --out "seq%03d.png" >seq.txt 2>&1 && [ -f seq000.png ] && [ -f seq002.png ]; then
	ok
else
	bad "--count 3 with %03d: $(cat seq.txt; ls)"
fi

# compaction without a vertex pass computes no ambient occlusion: the run
# says so once (not per frame); with --ao-rays 0 there is nothing to say
for c in atomic none; do
	if "$BIN" --size 64x48 --grid 12 --count 2 --compaction $c --out ao.png >ao.txt 2>&1; then
		n=$(grep -c "compaction $c computes no ambient occlusion" ao.txt)
		[ "$n" -eq 1 ] && ok || bad "--compaction $c: $n AO notices, want 1: $(cat ao.txt)"
	else
		bad "--compaction $c: $(cat ao.txt)"
	fi
	"$BIN" --size 64x48 --grid 12 --compaction $c --ao-rays 0 --out ao.png >ao.txt 2>&1 &&
		! grep -q "ambient occlusion" ao.txt && ok || bad "--compaction $c --ao-rays 0: $(cat ao.txt)"
done

# the world scene exports its mesh too (every block the world holds), no
# warning; the PLY is checked against the world rebuilt independently
# (tests/world_export_check.c: triangle count, block bounds, every vertex
# where Marching Cubes puts it by the CPU density).  Seed 7: the autopilot
# starts within 16 units of a surface (12 blocks, ~5 400 triangles)
CHECK_WORLD=${ISOTERRA_BUILD:-$(dirname "$BIN")}/tests/world_export_check
WX="--scene world --count 1 --size 96x64 --lod-levels 1 --view-distance 16 --block-cells 16 --seed 7"
# shellcheck disable=SC2086 # $WX: the options, one word each
if "$BIN" $WX --out world.png --export-mesh world.ply >world.txt 2>&1 && [ -s world.ply ]; then
	ok
	grep -q "ignored" world.txt && bad "world export still warns: $(cat world.txt)" || ok
	# shellcheck disable=SC2086
	"$CHECK_WORLD" world.ply $WX >check.txt 2>&1 && ok || bad "world export: $(cat check.txt)"
else
	bad "--scene world --export-mesh: $(cat world.txt)"
fi

# a flight that sees no terrain for 3 s is said once (the camera, the fly
# height); a flight over the ground says nothing of the kind
FX="--scene world --size 64x48 --count 45 --fps 10 --seed 7"
# shellcheck disable=SC2086 # $FX: the options, one word each
if "$BIN" $FX --fly-height 200 --out sky.png >sky.txt 2>&1; then
	n=$(grep -c "warning: world: no terrain in view for 3.0 s (the camera at .*fly_height 200" sky.txt)
	[ "$n" = 1 ] && ok || bad "--fly-height 200: want one 'no terrain in view' warning, got $n: $(cat sky.txt)"
else
	bad "--fly-height 200 run failed: $(cat sky.txt)"
fi
# shellcheck disable=SC2086
if "$BIN" $FX --out ground.png >ground.txt 2>&1; then
	grep -q "no terrain in view" ground.txt && bad "a flight over the ground warns: $(cat ground.txt)" || ok
else
	bad "default flight failed: $(cat ground.txt)"
fi

echo "cli: $pass passed, $fail failed"
[ $fail -eq 0 ]
