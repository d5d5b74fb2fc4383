#!/usr/bin/env bash
# Proves that two builds of vdgview move the camera the same: replays every shared GoldSrc
# map that has a graph in GRAPH_DIR with both builds (spawn routes, nav routes where a .nav
# sits beside the map, the playtests of testmaps/demos/ on their map), at 1/60 and 1/30 s and
# for each seed in SEEDS, and compares the VDG camera's per-frame CSVs byte for byte with the
# per-frame compute time removed (a wall-clock measurement, never identical).
#
# Faster than scripts/check-identical.sh when only the runtime changed: the graphs are given
# (e.g. the OUT/graphs folder of scripts/camera-report.sh) instead of compiled twice.
#
#   scripts/replay-identical.sh OLD_VDGVIEW NEW_VDGVIEW GRAPH_DIR
#
# Prints one line per replay that differs or that a build could not run, and a closing
# "N identical, N differ" line; exits 1 when anything differs. A replay both builds refuse
# (e.g. a map without clip hulls) counts as neither. SHARED overrides ../shared, OUT the
# scratch folder (default target/replay-identical), SEEDS the seeds (default "1 2"), JOBS
# the replays run at once (default 2).
set -euo pipefail
cd "$(dirname "$0")/.."
[ $# -eq 3 ] || { echo "usage: $0 OLD_VDGVIEW NEW_VDGVIEW GRAPH_DIR" >&2; exit 2; }
OLD=$(readlink -f "$1")
NEW=$(readlink -f "$2")
GRAPHS=$(readlink -f "$3")
for b in "$OLD" "$NEW"; do
    [ -x "$b" ] || { echo "$b: no such executable" >&2; exit 2; }
done
[ -d "$GRAPHS" ] || { echo "$GRAPHS: no such folder" >&2; exit 2; }
SHARED=$(readlink -f "${SHARED:-../shared}")
[ -d "$SHARED/testmaps/goldsrc" ] || { echo "replay-identical: $SHARED/testmaps/goldsrc is absent; nothing to replay" >&2; exit 2; }
OUT=${OUT:-target/replay-identical}
SEEDS=${SEEDS:-1 2}
JOBS=${JOBS:-2}
rm -rf "$OUT"
mkdir -p "$OUT"
OUT=$(readlink -f "$OUT")

# One job per map, route source, frame time and seed: NAME|BSP|VDG|ROUTES|DT|SEED.
for vdg in "$GRAPHS"/*.vdg; do
    name=$(basename "$vdg" .vdg)
    bsp=$(find "$SHARED/testmaps/goldsrc" -name "$name.bsp" | head -1)
    [ -n "$bsp" ] || continue
    routes=(spawns)
    [ -f "${bsp%.bsp}.nav" ] && routes+=("nav:${bsp%.bsp}.nav")
    for dem in "$SHARED"/testmaps/demos/*.dem; do
        [ -f "$dem" ] || continue
        # A demo belongs to the map whose file name ends in the map it was recorded on.
        map=$({ "$NEW" demo "$dem" 2>/dev/null || true; } | awk '$1 == "map" {print $2}')
        [ -n "$map" ] && [[ "$name" == *"$map" ]] && routes+=("demo:$dem")
    done
    for r in "${routes[@]}"; do
        for dt in 1/60 1/30; do
            for seed in $SEEDS; do
                echo "$name|$bsp|$vdg|$r|$dt|$seed"
            done
        done
    done
done >"$OUT/jobs.txt"

replay_pair() {
    IFS='|' read -r name bsp vdg routes dt seed <<<"$1"
    local kind=${routes%%:*} ok=()
    [ "$kind" = demo ] && kind="demo-$(basename "${routes#demo:}" .dem)"
    local tag="$name-$kind-${dt#1/}-s$seed"
    for side in old new; do
        local bin=$OLD dir="$OUT/$side/$tag"
        [ "$side" = new ] && bin=$NEW
        mkdir -p "$dir"
        if "$bin" replay "$bsp" "$vdg" --routes "$routes" --dt "$dt" --seed "$seed" \
            --camera vdg --csv "$dir" >/dev/null 2>"$dir/err"; then
            # Drop the micros column: the only figure that is a measurement of time.
            awk -F, 'NR == 1 {for (i = 1; i <= NF; i++) if ($i == "micros") m = i}
                     {out = ""; for (i = 1; i <= NF; i++) if (i != m) out = out (out == "" ? "" : ",") $i; print out}' \
                "$dir/vdg.csv" >"$dir/frames.csv"
            ok+=(1)
        else
            ok+=(0)
        fi
    done
    case "${ok[0]}${ok[1]}" in
        00) echo "REFUSED $tag" ;;
        11) cmp -s "$OUT/old/$tag/frames.csv" "$OUT/new/$tag/frames.csv" \
                && echo "SAME $tag" || echo "DIFF $tag" ;;
        *) echo "FAILED $tag (old ran: ${ok[0]}, new ran: ${ok[1]})" ;;
    esac
}
export -f replay_pair
export OLD NEW OUT
xargs -P "$JOBS" -I{} bash -c 'replay_pair "$@"' _ {} <"$OUT/jobs.txt" >"$OUT/result.txt"
grep -v -e '^SAME' -e '^REFUSED' "$OUT/result.txt" || true
same=$(grep -c '^SAME' "$OUT/result.txt" || true)
differ=$(grep -c -e '^DIFF' -e '^FAILED' "$OUT/result.txt" || true)
refused=$(grep -c '^REFUSED' "$OUT/result.txt" || true)
echo "$same identical, $differ differ ($refused refused by both builds)"
[ "$differ" -eq 0 ]
