#!/usr/bin/env bash
# Acceptance run of vdgview on real graphs: compiles every generated map and
# every GoldSrc map in ../shared/testmaps (nonfree/ too with --nonfree, for local
# measurement only) with `bsp2vdg -rl 1.0`, then runs `info`, the three queries
# and the renders (modes 1 and 3, top view; mode 2 must refuse cleanly) and
# prints one line per map with the render times. Renders go to target/vdgview-maps/.
#
# usage: scripts/vdgview-maps.sh [--nonfree]
set -euo pipefail
cd "$(dirname "$(readlink -f "$0")")/../.."
OUT=target/vdgview-maps
mkdir -p "$OUT"
cargo build --release -q -p bsp2vdg -p vdgview
B=./target/release/bsp2vdg
V=./target/release/vdgview
# The shared maps live beside the repository (SHARED overrides the folder).
SHARED=${SHARED:-../shared}
maps=(testdata/maps/*.bsp "$SHARED"/testmaps/goldsrc/*.bsp)
[ "${1:-}" = --nonfree ] && maps+=("$SHARED"/testmaps/goldsrc/nonfree/*.bsp)

ms() { sed -n 's/.*rendered in \([0-9]*\) ms.*/\1/p'; }
fail=0
printf '%-34s %9s %9s %8s %8s %8s  %s\n' map vertices faces mode1ms mode3ms topms queries
for m in "${maps[@]}"; do
    n=$(basename "$m" .bsp)
    g="$OUT/$n.vdg"
    if ! $B -rl 1.0 -quiet -savesamples -o "$g" "$m" >"$OUT/$n.compile.log" 2>&1; then
        printf '%-34s (bsp2vdg could not compile it: %s)\n' "$n" "$(tail -1 "$OUT/$n.compile.log")"
        continue
    fi
    info=$($V info "$g")
    verts=$(awk '/^vertices/ {print $2}' <<<"$info")
    faces=$(awk '/^faces/ {print $2}' <<<"$info")
    # A point in the middle of the vertex bounds and one near a corner.
    read -r x0 y0 z0 x1 y1 z1 < <(grep '^vertex bounds' <<<"$info" | tr -d '(),' | awk '{print $3, $4, $5, $7, $8, $9}')
    c=$(awk -v a="$x0" -v b="$x1" -v c="$y0" -v d="$y1" -v e="$z0" -v f="$z1" 'BEGIN {print (a+b)/2, (c+d)/2, (e+f)/2}')
    k=$(awk -v a="$x0" -v c="$y0" -v e="$z0" 'BEGIN {print a+40, c+40, e+40}')
    # shellcheck disable=SC2086
    q="$($V query "$g" clearance $c | head -1); $($V query "$g" visible $c $k); $($V query "$g" path $c $k | head -1)"
    s="$OUT/$n.samples.txt"
    t1=$($V render "$m" "$g" --mode 1 -o "$OUT/$n.mode1.png" 2>&1 | ms)
    t3=$($V render "$m" "$g" --mode 3 --samples "$s" -o "$OUT/$n.mode3.png" 2>&1 | ms)
    tt=$($V render "$m" "$g" --top -o "$OUT/$n.top.png" 2>&1 | ms)
    if $V render "$m" "$g" --mode 2 -o "$OUT/$n.mode2.png" 2>/dev/null; then
        echo "$n: mode 2 rendered although the graph has no reduction cost" >&2
        fail=1
    fi
    if [ -z "$t1" ] || [ -z "$t3" ] || [ -z "$tt" ]; then fail=1; fi
    printf '%-34s %9s %9s %8s %8s %8s  %s\n' "$n" "$verts" "$faces" "${t1:-FAIL}" "${t3:-FAIL}" "${tt:-FAIL}" "$q"
done
exit $fail
