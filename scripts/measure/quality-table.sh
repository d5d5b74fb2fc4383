#!/usr/bin/env bash
# The per-map before/after quality table (docs/quality-per-map.tsv): compiles every
# map with two builds of bsp2vdg at their default options (plus the second build unreduced,
# `-rl 1.0`), checks all three graphs with this checkout's `vdgview check --json --samples N
# --seed S` (so both builds are judged by the same checker) and prints one TSV row per map:
# reduction ratio and stop reason, vertices, file sizes, coverage (>= 32), walkable coverage
# at the standing origin and at head height, Visible's false negatives with both ends inside
# the volume, leak and false positives, and crouch coverage (GoldSrc, Quake 2 and 3: the eyes
# of the places where a player only fits crouching inside the volume, n/a where there are
# none); then the unreduced figures as `#` lines.
#   scripts/quality-table.sh [-samples N] [-seed S] BEFORE_BIN AFTER_BIN [MAP.bsp ...]
# Without maps: every GoldSrc, Quake 1, 2 and 3 map in ../shared/testmaps (nonfree too).
# BEFORE_BIN / AFTER_BIN are bsp2vdg executables (e.g. built from two commits with
# `git worktree`); a map either build cannot compile gets a `# MAP: compile failed` line.
# Takes about an hour over every shared map on two cores.
set -euo pipefail
cd "$(dirname "$(readlink -f "$0")")/../.."
samples=100000 seed=1
while [ $# -gt 0 ]; do
  case "$1" in
    -samples) samples=$2; shift 2 ;;
    -seed) seed=$2; shift 2 ;;
    -h|--help) sed -n '2,15p' "$0"; exit 0 ;;
    *) break ;;
  esac
done
if [ $# -lt 2 ]; then
  echo "usage: scripts/quality-table.sh [-samples N] [-seed S] BEFORE_BIN AFTER_BIN [MAP.bsp ...]" >&2
  exit 2
fi
before=$1 after=$2; shift 2
for b in "$before" "$after"; do
  [ -x "$b" ] || { echo "quality-table: $b is not an executable" >&2; exit 2; }
done
cargo build --release -q -p vdgview
check=./target/release/vdgview
shopt -s nullglob
maps=("$@")
if [ ${#maps[@]} -eq 0 ]; then
  maps=(../shared/testmaps/goldsrc/*.bsp ../shared/testmaps/goldsrc/nonfree/*.bsp
        ../shared/testmaps/quake1/*.bsp ../shared/testmaps/quake1/nonfree/*.bsp
        ../shared/testmaps/quake2/*.bsp ../shared/testmaps/quake3/*.bsp)
fi
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
echo "# vdgview check --samples $samples --seed $seed ($((samples / 10)) sight lines) on graphs compiled at the default options;"
echo "# before = $before ($("$before" -version 2>/dev/null | head -n1 || true)), after = $after; unreduced = after at -rl 1.0 (last lines)."
echo "# fn_inside: Visible's false negatives among the free sight lines with both ends inside the volume (inside_segments of them, after);"
echo "# fn_camera: the same on the sight lines from a camera's distance to standing player origins (vdgview check visible_fn_camera)."
echo "# fn_inside_se: its standard error, sqrt(p(1-p)/inside_segments) (about 0.25 points at 2 % with 10^5 samples: use 10^6 near a bound)."
printf 'map\tratio\tstop\tvertices\tbytes_before\tbytes_after\tcoverage_before\tcoverage_after\twalkable_before\twalkable_after\thead_before\thead_after\tfn_inside_before\tfn_inside_after\tinside_segments\tleak_after\tfp_after\tcrouch_before\tcrouch_after\tfn_inside_se\tfn_camera_before\tfn_camera_after\n'
unreduced=()
for m in "${maps[@]}"; do
  name=$(basename "$m" .bsp)
  name=${name#bspview-}
  ok=1
  for run in before after unreduced; do
    case $run in
      before) bin=$before opts=() ;;
      after) bin=$after opts=() ;;
      unreduced) bin=$after opts=(-rl 1.0) ;;
    esac
    if ! "$bin" -quiet --json "${opts[@]}" -o "$out/$run.vdg" "$m" > "$out/$run.json" 2> "$out/$run.err"; then
      echo "# $name: compile failed ($run): $(tail -n1 "$out/$run.err")"
      ok=0; break
    fi
    # A map without free space compiles to no graph: nothing to check.
    if [ ! -s "$out/$run.vdg" ]; then ok=0; echo "# $name: no graph ($run)"; break; fi
    "$check" check --json --samples "$samples" --seed "$seed" "$m" "$out/$run.vdg" > "$out/$run.check.json" || true
  done
  [ $ok = 1 ] || continue
  python3 - "$name" "$out" <<'PY'
import json, sys
name, d = sys.argv[1], sys.argv[2]
load = lambda f: json.load(open(f"{d}/{f}"))
cb, ca = load("before.json"), load("after.json")
kb, ka = load("before.check.json"), load("after.check.json")
share = lambda x: "n/a" if x is None else f"{x:.4f}"
ratio = ca["reduced_vertices"] / max(ca["reduce_vertices_before"], 1)
print("\t".join([
    name, f"{100 * ratio:.2f}%", ca["reduce_stop_reason"], str(ca["vertices"]),
    str(kb["bytes"]), str(ka["bytes"]),
    f"{kb['coverage']:.4f}", f"{ka['coverage']:.4f}",
    share(kb["walkable_coverage"]), share(ka["walkable_coverage"]),
    share(kb["walkable_coverage_head"]), share(ka["walkable_coverage_head"]),
    f"{kb['visible_fn_inside']:.4f}", f"{ka['visible_fn_inside']:.4f}",
    str(ka["free_segments_inside"]), f"{ka['leak']:.6f}", f"{ka['visible_fp']:.6f}",
    share(kb.get("crouch_coverage")), share(ka.get("crouch_coverage")),
    f"{(ka['visible_fn_inside'] * (1 - ka['visible_fn_inside']) / max(ka['free_segments_inside'], 1)) ** 0.5:.4f}",
    share(kb.get("visible_fn_camera")), share(ka.get("visible_fn_camera")),
]))
ku, cu = load("unreduced.check.json"), load("unreduced.json")
with open(f"{d}/unreduced.rows", "a") as f:
    f.write("#\t" + "\t".join([name, str(cu["vertices"]), share(ku["walkable_coverage"]),
        share(ku["walkable_coverage_head"]), f"{ku['coverage']:.4f}",
        f"{ku['visible_fn_inside']:.4f}", share(ku.get("crouch_coverage"))]) + "\n")
PY
done
echo "# unreduced (-rl 1.0), same check: map, vertices, walkable, head, coverage, fn_inside, crouch"
[ -f "$out/unreduced.rows" ] && cat "$out/unreduced.rows"
exit 0
