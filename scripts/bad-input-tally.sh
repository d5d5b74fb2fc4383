#!/usr/bin/env bash
# Bad inputs and faults against every binary, counted: clear errors, panics, others.
#
#   scripts/bad-input-tally.sh [BINDIR]     (default target/release; needs bsp2vdg, vdgview,
#                                            flowtile-bake there)
#
# Tries truncated and corrupted maps (generated ones, and the shared Quake 2/3 maps when
# ../shared/testmaps is present), truncated and corrupted .vdg and baked tiling files, NaN
# and impossible options, unwritable outputs, an output that is the input, duplicate map
# names, closed pipes (`| head -1`, `| true`) and full disks (`> /dev/full`, `2> /dev/full`).
# Each case is one line: the verdict, the exit status, the command, the first stderr line.
#   clear  - exit 1 or 2 with a one-line "error" message on stderr (what a failure should be)
#   ok     - a fault the tool should ride out (closed pipe, full log stream) and it did: exit 0
#            and the output file written
#   PANIC  - "panicked" on stderr, exit 101, or killed by a signal
#   OTHER  - anything else (exit 0 on bad input, silent failure, no message)
# Ends with the tally; exit 1 when any case panicked. Work files go to a temporary folder.
set -uo pipefail
cd "$(dirname "$0")/.."
BIN=$(cd "${1:-target/release}" && pwd)
B="$BIN/bsp2vdg"; V="$BIN/vdgview"; F="$BIN/flowtile-bake"
for exe in "$B" "$V" "$F"; do [ -x "$exe" ] || { echo "no $exe" >&2; exit 2; }; done
W=$(mktemp -d /tmp/bad-input-XXXXXX)
trap 'rm -rf "$W"' EXIT
declare -A COUNT=([clear]=0 [ok]=0 [PANIC]=0 [OTHER]=0)

verdict() { # verdict NAME RC STDERR_FILE [OUTPUT_THAT_MUST_EXIST]
    local name=$1 rc=$2 err=$3 must=${4:-} v
    if grep -q "panicked" "$err" || [ "$rc" = 101 ] || [ "$rc" -ge 128 ]; then v=PANIC
    elif [ -n "$must" ]; then
        if [ "$rc" = 0 ] && [ -s "$must" ]; then v=ok; else v=OTHER; fi
    elif { [ "$rc" = 1 ] || [ "$rc" = 2 ]; } && grep -qi "error" "$err"; then v=clear
    else v=OTHER; fi
    COUNT[$v]=$((COUNT[$v] + 1))
    printf '%-6s %3s  %s  | %s\n' "$v" "$rc" "$name" "$(grep -v '^\s*$' "$err" | head -1 | cut -c1-110)"
}

# try NAME CMD...: runs CMD (stdout discarded) and judges it as a bad input.
try() {
    local name=$1; shift
    timeout 120 "$@" >/dev/null 2>"$W/err"; verdict "$name" $? "$W/err"
}
# ride NAME MUST_EXIST SCRIPT: a fault to ride out, run through bash.
ride() {
    local name=$1 must=$2 script=$3
    rm -f "$must"
    timeout 120 bash -c "$script" 2>"$W/err"; verdict "$name" $? "$W/err" "$must"
}

MAP=testdata/maps/box_room.bsp
cp "$MAP" "$W/box.bsp"
"$B" -rl 1.0 -nolog -quiet "$W/box.bsp" -o "$W/good.vdg" || { echo "cannot compile $MAP" >&2; exit 2; }
"$F" tile --grid 4x4 -o "$W/good.ft" >/dev/null 2>&1 || true
SIZE=$(stat -c %s "$W/box.bsp")

# --- maps: truncated and corrupted (generated map, and real Quake 2/3 ones) ---
maps=("$W/box.bsp")
for d in quake2 quake3 quake1 goldsrc; do
    m=$(ls ../shared/testmaps/$d/*.bsp 2>/dev/null | head -1)
    [ -n "$m" ] && maps+=("$m")
done
i=0
for m in "${maps[@]}"; do
    size=$(stat -c %s "$m")
    for cut in 0 3 8 64 200 $((size / 3)) $((size / 2)) $((size - 1)); do
        i=$((i + 1)); head -c "$cut" "$m" >"$W/t$i.bsp"
        try "bsp2vdg truncated $(basename "$m") to $cut bytes" "$B" -nolog "$W/t$i.bsp" -o "$W/t$i.vdg"
        timeout 120 "$V" info "$W/t$i.bsp" >/dev/null 2>"$W/err"; rc=$?
        # Cutting the padding after the last lump leaves a valid map: exit 0 is right.
        if [ $rc = 0 ]; then echo "skip     0  vdgview info $(basename "$m") truncated to $cut: still a valid map"; else
            verdict "vdgview info truncated $(basename "$m") to $cut" $rc "$W/err"; fi
    done
    for off in 8 12 16 20 40 $((size / 2)); do
        i=$((i + 1)); cp "$m" "$W/c$i.bsp"
        printf '\xff\xff\xff\x7f' | dd of="$W/c$i.bsp" bs=1 seek="$off" conv=notrunc 2>/dev/null
        "$B" -nolog -quiet "$W/c$i.bsp" -o "$W/c$i.vdg" >/dev/null 2>"$W/err"; rc=$?
        # A corrupted byte may still give a valid map: then exit 0 is right.
        if [ $rc = 0 ]; then echo "skip     0  bsp2vdg $(basename "$m") corrupted at $off: still a valid map"; else
            verdict "bsp2vdg $(basename "$m") corrupted at $off" $rc "$W/err"; fi
    done
done
printf 'VBSP\x14\x00\x00\x00' >"$W/source.bsp"; head -c 2000 /dev/zero >>"$W/source.bsp"
try "bsp2vdg a Source map" "$B" -nolog "$W/source.bsp"
head -c 4096 /dev/urandom >"$W/noise.bsp"
try "bsp2vdg random bytes" "$B" -nolog "$W/noise.bsp"

# --- bad command lines ---
for opt in "-sd 0" "-sd -4" "-sd nan" "-sd inf" "-rl 2" "-rl nan" "-ms 0" "-ms 1" "-bb 0" "-md -1" \
    "-md nan" "-threads 100000" "-nosuchoption" "--stop-after bogus" "--rc bogus" "-sd" \
    "--check-samples 0 --baseline $W" "--baseline $W/nodir" "--tolerances $W/none.toml --baseline $W"; do
    # shellcheck disable=SC2086
    try "bsp2vdg $opt" "$B" $opt "$W/box.bsp" -o "$W/x.vdg"
done
try "bsp2vdg no map" "$B"
# No graph: a clear error naming the pointfile it wrote, exit 1.
try "bsp2vdg -md 100000 (empty graph)" "$B" -nolog -md 100000 "$W/box.bsp" -o "$W/empty.vdg"
try "bsp2vdg missing map" "$B" "$W/missing.bsp"
try "bsp2vdg a folder as map" "$B" "$W"
try "bsp2vdg -o the map itself" "$B" "$W/box.bsp" -o "$W/box.bsp"
ln -f "$W/box.bsp" "$W/link.vdg"
try "bsp2vdg -o a hard link to the map" "$B" "$W/box.bsp" -o "$W/link.vdg"
try "bsp2vdg -o a missing folder" "$B" "$W/box.bsp" -o "$W/no/such/x.vdg"
try "bsp2vdg -o an unwritable place" "$B" "$W/box.bsp" -o /proc/x.vdg
try "bsp2vdg -o a file as batch folder" "$B" "$W/box.bsp" "$W/t1.bsp" -o "$W/good.vdg"
mkdir -p "$W/a" "$W/b" "$W/out"; cp "$MAP" "$W/a/x.bsp"; cp "$MAP" "$W/b/x.bsp"
try "bsp2vdg two maps named x.bsp" "$B" "$W/a/x.bsp" "$W/b/x.bsp" -o "$W/out"
try "bsp2vdg the same map twice" "$B" "$W/a/x.bsp" "$W/a/x.bsp" -o "$W/out"
printf 'cuonts = 1\n' >"$W/typo.toml"
try "bsp2vdg tolerances typo" "$B" --baseline "$W" --tolerances "$W/typo.toml" "$W/box.bsp"
ride "bsp2vdg -logfile in a missing folder (compiles, warns)" "$W/lf.vdg" "'$B' -logfile '$W/no/x.log' '$W/box.bsp' -o '$W/lf.vdg' -rl 1 >/dev/null"

# --- faults on output streams: the compile must finish and write its files ---
ride "bsp2vdg | head -1" "$W/p1.vdg" "'$B' -rl 1 -verbose '$W/box.bsp' -o '$W/p1.vdg' | head -1 >/dev/null; exit \${PIPESTATUS[0]}"
ride "bsp2vdg | true" "$W/p2.vdg" "'$B' -rl 1 '$W/box.bsp' -o '$W/p2.vdg' | true; exit \${PIPESTATUS[0]}"
ride "bsp2vdg batch | true" "$W/out/t1.vdg" "cp '$W/box.bsp' '$W/t1.bsp'; '$B' -rl 1 -force '$W/box.bsp' '$W/t1.bsp' -o '$W/out' | true; exit \${PIPESTATUS[0]}"
ride "bsp2vdg > /dev/full" "$W/p3.vdg" "'$B' -rl 1 '$W/box.bsp' -o '$W/p3.vdg' >/dev/full"
ride "bsp2vdg 2> /dev/full (bar and errors)" "$W/p4.vdg" "'$B' -rl 1 -estimate '$W/box.bsp' -o '$W/p4.vdg' 2>/dev/full >/dev/null"
ride "bsp2vdg --json | head -c 10" "$W/p5.vdg" "'$B' -rl 1 --json '$W/box.bsp' -o '$W/p5.vdg' | head -c 10 >/dev/null; exit \${PIPESTATUS[0]}"
try "bsp2vdg --json > /dev/full (the report is lost)" bash -c "'$B' -rl 1 --json '$W/box.bsp' -o '$W/p6.vdg' >/dev/full"

# --- vdgview: corrupt graphs, bad queries, outputs, pipes ---
VS=$(stat -c %s "$W/good.vdg")
for cut in 0 4 16 100 $((VS / 2)) $((VS - 1)); do
    head -c "$cut" "$W/good.vdg" >"$W/t.vdg"
    try "vdgview info .vdg truncated to $cut" "$V" info "$W/t.vdg"
    try "vdgview query .vdg truncated to $cut" "$V" query "$W/t.vdg" clearance 0 0 0
done
for off in 0 8 64 $((VS / 2)) $((VS - 8)); do
    cp "$W/good.vdg" "$W/c.vdg"
    printf '\x55\xaa' | dd of="$W/c.vdg" bs=1 seek="$off" conv=notrunc 2>/dev/null
    try "vdgview info .vdg corrupted at $off" "$V" info "$W/c.vdg"
done
try "vdgview query NaN" "$V" query "$W/good.vdg" clearance nan 0 0
try "vdgview query bad kind" "$V" query "$W/good.vdg" teleport 0 0 0
try "vdgview query too few numbers" "$V" query "$W/good.vdg" visible 0 0 0
try "vdgview check another map's graph" "$V" check testdata/maps/two_rooms.bsp "$W/good.vdg" --samples 200
try "vdgview check --samples 0" "$V" check "$W/box.bsp" "$W/good.vdg" --samples 0
try "vdgview render to a missing folder" "$V" render "$W/box.bsp" "$W/good.vdg" -o "$W/no/x.png"
try "vdgview render --size 0x0" "$V" render "$W/box.bsp" "$W/good.vdg" -o "$W/x.png" --size 0x0
try "vdgview render --size 100000x100000" "$V" render "$W/box.bsp" "$W/good.vdg" -o "$W/x.png" --size 100000x100000
try "vdgview replay missing nav" "$V" replay "$W/box.bsp" "$W/good.vdg" --routes nav:"$W/none.nav"
try "vdgview view without a display" env -u DISPLAY "$V" view "$W/box.bsp"
try "vdgview info > /dev/full" bash -c "'$V' info '$W/good.vdg' >/dev/full"
for sub in "info $W/good.vdg" "info $W/box.bsp" "query $W/good.vdg clearance 0 0 0" \
    "check $W/box.bsp $W/good.vdg --samples 300" "replay $W/box.bsp $W/good.vdg --max-routes 1"; do
    for reader in "head -1 >/dev/null" "true"; do
        timeout 120 bash -c "'$V' $sub | $reader; exit \${PIPESTATUS[0]}" 2>"$W/err"; rc=$?
        if grep -q panicked "$W/err" || [ $rc = 101 ] || [ $rc -ge 128 ]; then verdict "vdgview $sub | $reader" $rc "$W/err"
        else COUNT[ok]=$((COUNT[ok] + 1)); printf '%-6s %3s  %s\n' ok $rc "vdgview ${sub%% *} | $reader"; fi
    done
done

# --- flowtile-bake ---
if [ -s "$W/good.ft" ]; then
    FS=$(stat -c %s "$W/good.ft")
    for cut in 0 4 16 $((FS / 2)) $((FS - 1)); do
        head -c "$cut" "$W/good.ft" >"$W/t.ft"
        try "flowtile-bake info tiling truncated to $cut" "$F" info "$W/t.ft"
        try "flowtile-bake render tiling truncated to $cut" "$F" render "$W/t.ft" -o "$W/t.png"
    done
    try "flowtile-bake render to a missing folder" "$F" render "$W/good.ft" -o "$W/no/x.png"
    for u in 0 -64 nan inf; do
        try "flowtile-bake render --tile-units $u" "$F" render "$W/good.ft" -o "$W/x.png" --tile-units "$u"
    done
    timeout 60 bash -c "'$F' info '$W/good.ft' | head -1 >/dev/null; exit \${PIPESTATUS[0]}" 2>"$W/err"; rc=$?
    if grep -q panicked "$W/err" || [ $rc = 101 ]; then verdict "flowtile-bake info | head -1" $rc "$W/err"
    else COUNT[ok]=$((COUNT[ok] + 1)); echo "ok     $rc  flowtile-bake info | head -1"; fi
fi
try "flowtile-bake tile --grid 0x0" "$F" tile --grid 0x0 -o "$W/z.ft"
try "flowtile-bake tile --set nonsense" "$F" tile --grid 4x4 --set a,b,c -o "$W/z.ft"
try "flowtile-bake tile to a missing folder" "$F" tile --grid 4x4 -o "$W/no/z.ft"
head -c 300 "$W/box.bsp" >"$W/cut.bsp"
try "flowtile-bake region on a truncated map" "$F" region "$W/cut.bsp" -o "$W/r.toml"
try "flowtile-bake count nonsense" "$F" count x y z

total=$((COUNT[clear] + COUNT[ok] + COUNT[PANIC] + COUNT[OTHER]))
echo
echo "tally ($BIN): $total cases: ${COUNT[clear]} clear errors, ${COUNT[ok]} faults ridden out, ${COUNT[PANIC]} panics, ${COUNT[OTHER]} other"
[ "${COUNT[PANIC]}" = 0 ]
