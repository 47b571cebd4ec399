#!/bin/sh
# isoterra — a GL limit too small for a pass stops the program with one line
# naming the limit, the value found, the need and the pass, and a non-zero
# exit (the limits lowered with ISOTERRA_GL_LIMIT_OVERRIDE, read only by
# app/gpu/gl_limits.c); limits just large enough still render.
#
# The needs are the driver's own counts: each program is introspected when
# it is linked (--verbose logs "PASS uses: N storage blocks (highest binding
# B), ..."), so this test reads them from a run on this driver instead of
# expecting numbers, lowers each limit to one below the largest need seen
# and expects the refusal to name exactly that need and a pass that has it;
# at the need itself the picture is made.  Then Mali's Panfrost (8 storage
# blocks, 8 binding points) runs every configuration.
BIN=${1:-${ISOTERRA_BIN:-./build/isoterra}}
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
MAX_MSG_LINES=1
NO_OUTPUT=$T/x.png
. "$(dirname "$0")/cli_lib.sh"
EX=${ISOTERRA_SRC:-$(cd "$(dirname "$0")/.." && pwd)}/docs/examples
export XDG_CACHE_HOME="$T/cache"

cd "$T" || exit 1
small="--size 64x48 --grid 8 --out $T/x.png"
lowered() { # "LIMIT=VALUE" "regex" [args]
	o=$1
	pat=$2
	shift 2
	# shellcheck disable=SC2086 # $small is a word list
	ISOTERRA_GL_LIMIT_OVERRIDE=$o expect_fail "$pat" $small "$@"
}
renders() { # "LIMIT=VALUE,..." what [args]
	o=$1
	what=$2
	shift 2
	rm -f "$T/x.png"
	# shellcheck disable=SC2086
	if ISOTERRA_GL_LIMIT_OVERRIDE=$o "$BIN" $small "$@" >run.txt 2>&1 && [ -s "$T/x.png" ]; then
		ok
	else
		bad "$what ($o): $(tail -3 run.txt)"
	fi
}

# the needs as this driver counts them, for a volume and a world run
# shellcheck disable=SC2086
"$BIN" $small --verbose >/dev/null 2>uses.txt || bad "the plain run failed: $(tail -3 uses.txt)"
# shellcheck disable=SC2086
"$BIN" $small --scene world --count 2 --verbose >/dev/null 2>>uses.txt || bad "the world run failed"
# largest value of field $1 (awk on the "uses:" lines) -> "N PASS"
largest() {
	grep ' uses: ' uses.txt | sed 's/^isoterra: debug: //' | awk -v f="$1" '
		{ i = index($0, " uses: "); pass = substr($0, 1, i - 1); rest = substr($0, i + 7)
		  n = split(rest, w, /[ ,()\/]+/)
		  v = -1
		  if (f == "ssbo") v = w[1]
		  if (f == "binding") for (k = 1; k < n; k++) if (w[k] == "binding") { v = w[k + 1] + 1; break }
		  if (v > best) { best = v; who = pass } }
		END { print best " " who }'
}
ssbo=$(largest ssbo)
bind=$(largest binding)
n_ssbo=${ssbo%% *}
who_ssbo=${ssbo#* }
n_bind=${bind%% *}
echo "the driver counts: $n_ssbo storage blocks at most ($who_ssbo), binding points 0..$((n_bind - 1))"
if [ -n "$n_ssbo" ] && [ "$n_ssbo" -ge 1 ] && [ "$n_bind" -ge 1 ]; then ok; else bad "no program's use logged"; fi
# the design's budget (app/gpu/abi.h): without curves the OpenGL ES 3.1
# minimums, four blocks a pass and binding points 0..3
if [ "$n_ssbo" -le 4 ] && [ "$n_bind" -le 4 ]; then ok; else bad "over the budget: $n_ssbo blocks, $n_bind bindings"; fi

# one below the largest need: refused, naming that need (and, for the
# blocks, a pass that has it); the world checks the same way
re_who=$(printf '%s' "$who_ssbo" | sed 's/[][().*+?^$|\\]/\\&/g')
lowered "GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS=$((n_ssbo - 1))" \
	"^isoterra: error: GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS is $((n_ssbo - 1)) on .*, isoterra needs $n_ssbo \\(.*\\)$" \
	--scene world --count 2
lowered "GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS=$((n_ssbo - 1))" \
	"^isoterra: error: GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS is $((n_ssbo - 1)) on .*, isoterra needs $n_ssbo \\($re_who\\)$"
lowered "GL_MAX_COMBINED_SHADER_STORAGE_BLOCKS=$((n_ssbo - 1))" \
	"GL_MAX_COMBINED_SHADER_STORAGE_BLOCKS is $((n_ssbo - 1)) on .*needs $n_ssbo"
lowered "GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS=$((n_bind - 1))" \
	"GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS is $((n_bind - 1)) on .*needs $n_bind \\("
lowered GL_MAX_COMPUTE_WORK_GROUP_INVOCATIONS=32 "GL_MAX_COMPUTE_WORK_GROUP_INVOCATIONS is 32 on .*needs 64"
lowered "GL_MAX_COMPUTE_WORK_GROUP_SIZE[0]=16" "GL_MAX_COMPUTE_WORK_GROUP_SIZE\[0\] is 16 on .*needs 64"
lowered GL_MAX_COMPUTE_UNIFORM_BLOCKS=0 "GL_MAX_COMPUTE_UNIFORM_BLOCKS is 0 on .*needs [12] \\("
lowered GL_MAX_UNIFORM_BUFFER_BINDINGS=1 "GL_MAX_UNIFORM_BUFFER_BINDINGS is 1 on .*needs 2 \\("
lowered GL_MAX_COMPUTE_SHARED_MEMORY_SIZE=128 "GL_MAX_COMPUTE_SHARED_MEMORY_SIZE is 128 on .*needs 256"
lowered GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS=4 "GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS is 4 on .*needs 8 \\(render"
lowered GL_MAX_3D_TEXTURE_SIZE=8 "GL_MAX_3D_TEXTURE_SIZE is 8 on .*needs 16"
lowered GL_MAX_SHADER_STORAGE_BLOCK_SIZE=65536 "GL_MAX_SHADER_STORAGE_BLOCK_SIZE is 65536 on .*needs 134217728"
lowered GL_NOT_A_LIMIT=1 "ISOTERRA_GL_LIMIT_OVERRIDE: 'GL_NOT_A_LIMIT=1' names no checked limit"
# exactly what is needed renders
renders "GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS=$n_ssbo,GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS=$n_bind" "limits at the need"

# Mali's Panfrost: 8 storage blocks per stage and combined, 8 binding points
pan="GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS=8,GL_MAX_COMBINED_SHADER_STORAGE_BLOCKS=8"
pan="$pan,GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS=8,GL_MAX_FRAGMENT_SHADER_STORAGE_BLOCKS=8"
renders "$pan" "Panfrost: the default volume"
renders "$pan" "Panfrost: the world" --scene world --count 3
renders "$pan" "Panfrost: curves over a heightmap" --field heightmap --heightmap "$EX/hill.png" --curves "$EX/tunnel_road.csv"
renders "$pan" "Panfrost: the world with curves" --scene world --count 3 --curves "$EX/tunnel_road.csv"
renders "$pan" "Panfrost: a control map" --control-map "$EX/control_half.png"
renders "$pan" "Panfrost: atomic compaction" --compaction atomic
renders "$pan" "Panfrost: V4L2 output" --v4l2 /dev/video-nonexistent
# the OpenGL ES 3.1 minimums (4 blocks, 4 binding points): any conformant
# driver runs the default volume and the world; curves take a fifth block
es31="GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS=4,GL_MAX_COMBINED_SHADER_STORAGE_BLOCKS=4,GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS=4"
renders "$es31" "ES 3.1 minimums: the default volume"
renders "$es31" "ES 3.1 minimums: the world" --scene world --count 3
renders "$es31" "ES 3.1 minimums: the caves preset's world" --scene world --count 3 --preset caves
renders "$es31" "ES 3.1 minimums: atomic compaction" --compaction atomic
lowered "$es31" "^isoterra: error: GL_MAX_.* is 4 on .*, isoterra needs 5 \\(.*\\)$" --curves "$EX/tunnel_road.csv"

echo "gl_limits_cli: $pass passed, $fail failed"
[ $fail -eq 0 ]
