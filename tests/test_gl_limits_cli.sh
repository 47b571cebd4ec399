#!/bin/sh
# isoterra — a GL limit too small for a pass stops the program at start with
# one line naming the limit, the value needed and the value found, and a
# non-zero exit (the limits lowered with ISOTERRA_GL_LIMIT_OVERRIDE, read
# only by app/gpu/gl_limits.c); limits just large enough still render.
BIN=${1:-${ISOTERRA_BIN:-./build/isoterra}}
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
MAX_MSG_LINES=1
NO_OUTPUT=$T/x.png
. "$(dirname "$0")/cli_lib.sh"

cd "$T" || exit 1
small="--size 64x48 --grid 8 --out $T/x.png"
lowered() { # "LIMIT=VALUE" "regex" [args]
	o=$1
	pat=$2
	shift 2
	# shellcheck disable=SC2086 # $small is a word list
	ISOTERRA_GL_LIMIT_OVERRIDE=$o expect_fail "$pat" $small "$@"
}
lowered GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS=4 \
	"^isoterra: error: GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS is 4 on .*, isoterra needs 10 \(mc_vertices.comp \(WITH_AO\)\)$"
lowered GL_MAX_COMBINED_SHADER_STORAGE_BLOCKS=8 "GL_MAX_COMBINED_SHADER_STORAGE_BLOCKS is 8 on .*needs 10"
lowered GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS=8 "GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS is 8 on .*needs 15 \(density.comp"
lowered GL_MAX_COMPUTE_WORK_GROUP_INVOCATIONS=32 "GL_MAX_COMPUTE_WORK_GROUP_INVOCATIONS is 32 on .*needs 64"
lowered "GL_MAX_COMPUTE_WORK_GROUP_SIZE[0]=16" "GL_MAX_COMPUTE_WORK_GROUP_SIZE\[0\] is 16 on .*needs 64"
lowered GL_MAX_COMPUTE_TEXTURE_IMAGE_UNITS=2 "GL_MAX_COMPUTE_TEXTURE_IMAGE_UNITS is 2 on .*needs 5 \(density.comp\)"
lowered GL_MAX_COMPUTE_SHARED_MEMORY_SIZE=128 "GL_MAX_COMPUTE_SHARED_MEMORY_SIZE is 128 on .*needs 256"
lowered GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS=4 "GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS is 4 on .*needs 8"
lowered GL_MAX_3D_TEXTURE_SIZE=8 "GL_MAX_3D_TEXTURE_SIZE is 8 on .*needs 16"
lowered GL_MAX_SHADER_STORAGE_BLOCK_SIZE=65536 "GL_MAX_SHADER_STORAGE_BLOCK_SIZE is 65536 on .*needs 134217728"
lowered GL_MAX_IMAGE_UNITS=0 "GL_MAX_IMAGE_UNITS is 0 on .*needs 1"
lowered GL_NOT_A_LIMIT=1 "ISOTERRA_GL_LIMIT_OVERRIDE: 'GL_NOT_A_LIMIT=1' names no checked limit"
# the streaming world checks the same limits
lowered GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS=9 "GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS is 9 on .*needs 10" --scene world
# exactly what is needed renders
if ISOTERRA_GL_LIMIT_OVERRIDE="GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS=10,GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS=15" \
	"$BIN" $small >run.txt 2>&1 && [ -s "$T/x.png" ]; then
	ok
else
	bad "limits exactly at the need: $(cat run.txt)"
fi

echo "gl_limits_cli: $pass passed, $fail failed"
[ $fail -eq 0 ]
