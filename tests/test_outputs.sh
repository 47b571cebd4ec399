#!/bin/sh
# isoterra — outputs end to end: every destination checked before any work,
# every file written whole or not at all (a run that fails, is stopped by
# SIGINT/SIGTERM or killed by SIGKILL leaves the previous files as they
# were), exact Y4M frame rates, write errors with their reason, and the
# progress bar on a terminal.
BIN=${1:-${ISOTERRA_BIN:-./build/isoterra}}
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
. "$(dirname "$0")/cli_lib.sh"
cd "$T" || exit 1
S="--size 64x48 --grid 12"

# previous files the runs below must leave alone
prev() { for f in "$@"; do printf 'previous %s\n' "$f" >"$f"; done; }
intact() { # file...: each still holds what prev wrote
	for f in "$@"; do
		[ "$(cat "$f" 2>/dev/null)" = "previous $f" ] || { bad "$f was changed: $(head -c 40 "$f" | od -c | head -2)"; return; }
	done
	ok
}
no_temps() { # no temp file left beside the targets
	left=$(ls -a | grep -E '\.[A-Za-z0-9]{6}$' | grep -v '^\.\.*$')
	[ -z "$left" ] && ok || bad "temp files left ($1): $left"
}

# whole_y4m FILE FRAMES: the header and FRAMES frames of 64x48
whole_y4m() { [ "$(wc -c <"$1")" -eq $(($(head -1 "$1" | wc -c) + $2 * (6 + 64 * 48 * 3 / 2))) ]; }
# whole_png FILE: ends with the IEND chunk
whole_png() { tail -c 8 "$1" | od -An -c | tr -d ' \n' | grep -q 'IEND'; }
# whole_ply FILE: the header's vertices (24 bytes) and faces (13 bytes) all there
whole_ply() {
	hl=$(head -c 400 "$1" | grep -a -b -o 'end_header' | head -1 | cut -d: -f1)
	nv=$(head -c 400 "$1" | grep -a 'element vertex' | cut -d' ' -f3)
	nf=$(head -c 400 "$1" | grep -a 'element face' | cut -d' ' -f3)
	[ -n "$hl" ] && [ "$(wc -c <"$1")" -eq $((hl + 11 + nv * 24 + nf * 13)) ]
}
# ---- checked before any work --------------------------------------------------
prev o.png
expect_fail "export_mesh: cannot write '/nonexistent/m.ply': directory '/nonexistent'" $S --out o.png --export-mesh /nonexistent/m.ply
intact o.png
expect_fail "out: cannot write 'nodir/o.png'" $S --out nodir/o.png
expect_fail "out: cannot write 'o.png/x.png'.*not a directory" $S --out o.png/x.png
mkdir adir.png
expect_fail "out: cannot write 'adir.png': it is a directory" $S --out adir.png
# a %0Nd pattern too long for the last frame's name: refused, never cut
expect_fail "out: 'f%0250d.png' is too long a file name" $S --out 'f%0250d.png'
long=$(printf 'd%.0s' $(seq 1 200))
mkdir "$long"
expect_fail "too long a file name for the last frame's number" $S --count 2 --out "$long/f%0248d.png"
[ -z "$(ls "$long")" ] && ok || bad "refused run wrote into $long: $(ls "$long")"
# one that fits: written under exactly its name
z60=$(printf '0%.0s' $(seq 1 59))
if "$BIN" $S --count 2 --out "$long/f%060d.png" >l.txt 2>&1 && [ -s "$long/f${z60}1.png" ]; then ok; else bad "long pattern: $(cat l.txt; ls "$long")"; fi
# many zero flags: printf's meaning (no width), nothing cut
if "$BIN" $S --count 2 --out 'f%00000000000000000000000000000000000d.png' >z.txt 2>&1 && [ -s f0.png ] && [ -s f1.png ]; then
	ok
else
	bad "many zero flags: $(cat z.txt; ls)"
fi
# the extension is decided once, in any case
if "$BIN" $S --count 2 --out up.Y4M >up.txt 2>&1 && head -c 9 up.Y4M | grep -q YUV4MPEG2; then ok; else bad "up.Y4M: $(cat up.txt)"; fi
# leading white space in numbers is refused like any other stray character
expect_fail "grid: ' 16' is not an integer" --grid ' 16'
expect_fail "fps: ' 30' is not a number" --fps ' 30'
# a config file starting with a UTF-8 byte order mark: accepted
printf '\357\273\277grid = 12\n' >bom.conf
"$BIN" --size 64x48 --config bom.conf --out bom.png >bom.txt 2>&1 && grep -q "grid 12^3" bom.txt && ok ||
	bad "config with a BOM: $(cat bom.txt)"
printf '\357\273\277gridd = 12\n' >bom2.conf
expect_fail "^isoterra: error: bom2.conf:1: unknown parameter 'gridd'" --config bom2.conf
grep -q "$(printf '\357\273\277')" err && bad "the message shows the byte order mark" || ok

# ---- Y4M: exact frame rates, write errors with their reason ---------------------
for r in "29.97 F30000:1001" "0.2 F1:5" "25 F25:1" "59.94 F60000:1001" "23.976 F24000:1001" "12.5 F25:2"; do
	set -- $r
	"$BIN" $S --count 1 --fps "$1" --out fps.y4m >fps.txt 2>&1 && head -1 fps.y4m | grep -q " $2 " && ok ||
		bad "--fps $1: want $2 in '$(head -1 fps.y4m)' $(cat fps.txt)"
done
("$BIN" $S --count 200 --out - 2>pipe.txt; echo $? >pipe.rc) | head -c 100 >/dev/null
rc=$(cat pipe.rc)
[ "$rc" -ne 0 ] && [ "$rc" -lt 128 ] && grep -q "stdout failed: Broken pipe" pipe.txt && ok ||
	bad "--out - | head: exit $rc, $(cat pipe.txt)"
"$BIN" $S --count 2 --out - >/dev/full 2>full.txt
rc=$?
[ $rc -eq 1 ] && grep -q "No space left on device" full.txt && ok || bad "--out - >/dev/full: exit $rc, $(cat full.txt)"

# ---- a mesh clamped at its vertex capacity: only whole triangles, said so ---------
if "$BIN" --size 64x48 --grid 16 --max-vertices 300 --out c.png --export-mesh c.ply >clamp.txt 2>&1; then
	grep -q "export_mesh: the mesh was clamped at its capacity: [0-9]* incomplete triangles left out of 'c.ply'" clamp.txt &&
		ok || bad "clamped export not reported: $(cat clamp.txt)"
	hl=$(head -c 400 c.ply | grep -a -b -o 'end_header' | head -1 | cut -d: -f1)
	nv=$(head -c 400 c.ply | grep -a 'element vertex' | cut -d' ' -f3)
	# every face: count 3, three distinct indices below the vertex count
	bad_faces=$(tail -c +$((hl + 12 + nv * 24)) c.ply | od -An -v -tu1 | tr -s ' \n' '\n\n' | grep . |
		awk -v nv="$nv" '{ b[n++] = $1 } END {
			for (f = 0; f + 13 <= n; f += 13) {
				if (b[f] != 3) { bad++; continue }
				for (k = 0; k < 3; k++) i[k] = b[f+1+4*k] + 256 * (b[f+2+4*k] + 256 * (b[f+3+4*k] + 256 * b[f+4+4*k]))
				if (i[0] == i[1] || i[1] == i[2] || i[0] == i[2] || i[0] >= nv || i[1] >= nv || i[2] >= nv) bad++
			}
			print bad + 0 }')
	[ "$bad_faces" = 0 ] && whole_ply c.ply && ok || bad "clamped PLY: $bad_faces incomplete faces"
else
	bad "clamped export failed: $(cat clamp.txt)"
fi

# ---- the progress bar on a terminal: every frame, also for one PNG --------------
if command -v script >/dev/null 2>&1; then
	script -qec "'$BIN' $S --count 4 --out single.png" /dev/null >bar.txt 2>&1
	tr '\r' '\n' <bar.txt | grep -q '^\[##########  *\] 1/4' && tr '\r' '\n' <bar.txt | grep -q '\] 4/4' && ok ||
		bad "progress bar on a terminal: $(tr '\r' '\n' <bar.txt)"
else
	echo "no script(1): progress bar not checked"
fi

# ---- SIGINT / SIGTERM before the last frame: 128 + signal, nothing written -------
# wait_temp NAME PID: until the run's temp file exists (it is rendering frames)
wait_temp() {
	while kill -0 "$2" 2>/dev/null && ! ls -a | grep -Eq "^$1\.[A-Za-z0-9]{6}$"; do sleep 0.05; done
}
for sig in INT:130 TERM:143; do
	prev stop.y4m
	"$BIN" $S --count 100000 --out stop.y4m >sig.txt 2>&1 &
	pid=$!
	wait_temp stop.y4m $pid
	kill -"${sig%:*}" $pid
	wait $pid
	rc=$?
	[ $rc -eq "${sig#*:}" ] && grep -q "stopped by SIG${sig%:*}" sig.txt && ok ||
		bad "SIG${sig%:*} during --count: exit $rc (want ${sig#*:}): $(cat sig.txt)"
	intact stop.y4m
	no_temps "SIG${sig%:*}"
done

# ---- SIGKILL at random moments: every target previous or whole ------------------
whole_y4m_30() { whole_y4m "$1" 30; }
# target_ok FILE CHECK...: previous, or whole by CHECK
target_ok() {
	f=$1
	shift
	if [ "$(cat "$f" 2>/dev/null)" = "previous $f" ] || "$@" "$f"; then ok; else bad "$f partial after SIGKILL ($(wc -c <"$f") bytes)"; fi
}
seed=$(od -An -tu4 -N4 /dev/urandom | tr -d ' ')
echo "SIGKILL moments from seed $seed"
for i in 1 2 3 4 5 6; do
	delay=$(awk -v s="$seed" -v i="$i" 'BEGIN { srand(s + i); printf "%.2f", rand() * 1.5 }')
	prev k.y4m k0.png k1.png k2.png k3.png k.ply
	case $i in
	1 | 4) "$BIN" $S --count 30 --out k.y4m >/dev/null 2>&1 & ;;
	2 | 5) "$BIN" $S --count 4 --out 'k%d.png' >/dev/null 2>&1 & ;;
	*) "$BIN" --size 64x48 --grid 48 --count 3 --out k0.png --export-mesh k.ply >/dev/null 2>&1 & ;;
	esac
	pid=$!
	sleep "$delay"
	kill -KILL $pid 2>/dev/null
	wait $pid 2>/dev/null
	target_ok k.y4m whole_y4m_30
	for f in k0.png k1.png k2.png k3.png; do target_ok $f whole_png; done
	target_ok k.ply whole_ply
	rm -f k*.??????
done

echo "outputs: $pass passed, $fail failed"
[ $fail -eq 0 ]
