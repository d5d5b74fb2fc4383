#!/usr/bin/env bash
# Quality of the compiled graphs against each map's own BSP (docs/design/quality.md):
# compiles every generated map and every GoldSrc, Quake 1, 2 and 3 map in ../shared/testmaps
# (nonfree too, when present), then runs `vdgview check` with N points (default 10^6) and N/10
# segments.
# Prints one row per map: counts, sizes, seconds per stage, leak, coverage, walkable coverage
# (standing player origin and head), visible fp/fn (fn_camera: on the sight lines from a
# camera's distance to standing origins, both ends inside).
#   scripts/quality-report.sh [N] [extra bsp2vdg options, e.g. -rl 1.0]
# Maps with a CS bot nav mesh beside them (MAP.nav) get the walkable sampler cross-checked
# against the mesh's floor points (`vdgview` example walkable_nav) as `#` lines.
#   MAPS="path/a.bsp path/b.bsp" scripts/quality-report.sh ...   (only these maps)
set -euo pipefail
cd "$(dirname "$(readlink -f "$0")")/../.."
n=${1:-1000000}; shift || true
opts=("$@"); [ ${#opts[@]} -eq 0 ] && opts=(-rl 1.0)
cargo build --release -q -p bsp2vdg -p vdgview
cargo build --release -q -p lab --bin walkable_nav
out=$(mktemp -d)
shopt -s nullglob
if [ -n "${MAPS:-}" ]; then
  # shellcheck disable=SC2206
  maps=($MAPS)
else
  maps=(testdata/maps/*.bsp ../shared/testmaps/goldsrc/*.bsp ../shared/testmaps/goldsrc/nonfree/*.bsp
        ../shared/testmaps/quake1/*.bsp ../shared/testmaps/quake1/nonfree/*.bsp
        ../shared/testmaps/quake2/*.bsp ../shared/testmaps/quake3/*.bsp)
fi
printf '%-32s %7s %8s %8s %8s %9s %7s %7s %7s %9s %8s %9s %9s %9s %9s %9s %9s %9s\n' map samples tets inner_v inner_f vertices faces bytes secs leak coverage walkable walk_head vis_fp vis_fn fn_inside fn_query fn_camera
for m in "${maps[@]}"; do
  name=$(basename "$m" .bsp)
  if ! ./target/release/bsp2vdg -quiet --json "${opts[@]}" -o "$out/$name.vdg" "$m" > "$out/$name.json" 2> "$out/$name.err"; then
    printf '%-32s compile failed: %s\n' "$name" "$(tail -n1 "$out/$name.err")"; continue
  fi
  ./target/release/vdgview check --json --samples "$n" "$m" "$out/$name.vdg" > "$out/$name.check.json" || true
  python3 - "$name" "$out/$name.json" "$out/$name.check.json" <<'PY'
import json, sys
name, c, k = sys.argv[1], json.load(open(sys.argv[2])), json.load(open(sys.argv[3]))
# Walkable coverage is null on a map with no standing places: printed n/a.
share = lambda x: "n/a" if x is None else f"{x:.4f}"
print(f"{name[:32]:<32} {c['samples']:>7} {c['tetrahedra']:>8} {c['inner_vertices']:>8} {c['inner_faces']:>8} {c['vertices']:>9} {c['vdg_faces']:>7} {c['bytes']:>7} {c['seconds']['total']:>7.1f} {k['leak']:>9.6f} {k['coverage']:>8.4f} {share(k['walkable_coverage']):>9} {share(k['walkable_coverage_head']):>9} {k['visible_fp']:>9.6f} {k['visible_fn']:>9.4f} {k['visible_fn_inside']:>9.4f} {k['visible_fn_query']:>9.4f} {share(k.get('visible_fn_camera')):>9}")
PY
  # Maps with a CS bot nav mesh beside them: the walkable sampler cross-checked against it.
  if [ -f "${m%.bsp}.nav" ]; then
    ./target/release/walkable_nav "$m" "${m%.bsp}.nav" "$out/$name.vdg" 20000 | sed 's/^/#   /'
  fi
done
rm -rf "$out"
