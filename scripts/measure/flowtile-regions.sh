#!/usr/bin/env bash
# Regions from real maps: runs `flowtile-bake region` on every
# GoldSrc, Quake 1, Quake 2 and Quake 3 map in ../shared/testmaps (SHARED overrides), tiles each
# region spec, and prints one line per map: floor, grid, open slots, sources /
# sinks, extraction seconds (wall and the process's CPU), tiling result, area
# against the designed direction. Outputs go to a temporary folder (OUT
# overrides). Usage: scripts/flowtile-regions.sh [TILE]
set -uo pipefail
cd "$(dirname "$(readlink -f "$0")")/../.."
TILE=${1:-64}
SHARED=${SHARED:-../shared}
OUT=${OUT:-$(mktemp -d /tmp/flowtile-regions.XXXXXX)}
mkdir -p "$OUT"
if [ ! -d "$SHARED/testmaps" ]; then
  echo "skip: $SHARED/testmaps not found" >&2
  exit 0
fi
nice cargo build --release -q -p flowtile-bake || exit 1
BIN=target/release/flowtile-bake
printf '%-44s %8s %9s %6s %7s %9s %8s %s\n' map floor grid open src/snk region_s cpu_s tiling
fail=0
for map in $(find "$SHARED/testmaps/goldsrc" "$SHARED/testmaps/quake1" "$SHARED/testmaps/quake2" "$SHARED/testmaps/quake3" -name '*.bsp' 2>/dev/null | sort); do
  name=$(basename "$map" .bsp)
  start=$(date +%s.%N)
  if ! json=$( { /usr/bin/time -f '%U' -o "$OUT/$name.cpu" nice "$BIN" region "$map" --tile "$TILE" \
        -o "$OUT/$name.toml" --picture "$OUT/$name.png" --json; } 2>"$OUT/$name.err"); then
    if grep -q 'is not read yet' "$OUT/$name.err"; then
      printf '%-44s skipped: %s\n' "$name" "$(sed 's/.*: \([A-Za-z0-9 ]* BSP ([A-Z0-9 ]*)\) is not read yet.*/\1 is not read yet/' "$OUT/$name.err" | tail -1)"
    else
      printf '%-44s FAILED: %s\n' "$name" "$(tail -1 "$OUT/$name.err")"
      fail=$((fail + 1))
    fi
    continue
  fi
  read -r floor w h open src snk secs < <(python3 -c 'import json,sys; d=json.loads(sys.argv[1]); print("%.0f %d %d %d %d %d %.3f" % (d["floor"], d["width"], d["height"], d["open_slots"], d["sources"], d["sinks"], d["extract_seconds"]))' "$json")
  tiled=$(nice "$BIN" tile "$OUT/$name.toml" -o "$OUT/$name.ftb" --json 2>&1 | python3 -c 'import json,sys
t=sys.stdin.read()
try:
    d=json.loads(t); a=d["against_main_direction"]
    print("ok %d tiles, %.1f ms, against %s" % (d["tiles_used"], d["seconds"]*1e3, "-" if a is None else "%.1f%%" % (a*100)))
except Exception: print("FAILED: " + t.strip().splitlines()[-1])')
  printf '%-44s %8s %4sx%-4s %6s %3s/%-3s %9s %8s %s\n' "$name" "$floor" "$w" "$h" "$open" "$src" "$snk" "$secs" "$(cat "$OUT/$name.cpu")" "$tiled"
done
echo "outputs in $OUT"
exit $fail
