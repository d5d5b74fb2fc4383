#!/usr/bin/env bash
# Coverage against the reduction ratio: compiles each map at several -rl
# values, measures walkable coverage, coverage (>= 32) and Visible's false negatives
# with both ends inside the volume with `vdgview check`, writes the table and draws it
# (vdgview example reduction_curve; the sight lines as 100 % - FN). With the keep rule the
# reduction may stop above -rl ("nothing_removable"): the ratio column is what it reached.
# Each -opts "..." is one series of compile options (e.g. -opts "" -opts "-sd 12 -md 4"):
# every map is compiled with each at every -rl. A second plot, OUT-vertices.png, draws
# Visible's false negatives against the vertices kept (vdgview example fn_vertices): what
# more vertices buy along a series, and what a finer graph buys at the same vertex count.
#   scripts/reduction-curve.sh [-samples N] [-rl "0.2 0.1 0.05 0.025 0.0125"] [-opts "..."]... OUT.png MAP.bsp...
set -euo pipefail
cd "$(dirname "$(readlink -f "$0")")/../.."
N=200000
RLS="0.2 0.1 0.05 0.025 0.0125"
OPTS=()
while [[ $# -gt 0 && "$1" == -* ]]; do
    case "$1" in
        -samples) N="$2"; shift 2 ;;
        -rl) RLS="$2"; shift 2 ;;
        -opts) OPTS+=("$2"); shift 2 ;;
        *) echo "unknown option $1" >&2; exit 2 ;;
    esac
done
[[ $# -ge 2 ]] || { echo "usage: $0 [-samples N] [-rl LIST] [-opts OPTIONS]... OUT.png MAP.bsp..." >&2; exit 2; }
[[ ${#OPTS[@]} -gt 0 ]] || OPTS=("")
png="$1"; shift
cargo build --release -q -p bsp2vdg -p vdgview
cargo build --release -q -p lab --bin reduction_curve --example fn_vertices
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT
table="${png%.png}.tsv"
printf 'map\trl\tratio\twalkable\tcoverage\tstop\tfn_inside\tvertices\toptions\n' > "$table"
for m in "$@"; do
    name=$(basename "$m" .bsp)
    for opts in "${OPTS[@]}"; do
        for rl in $RLS; do
            # shellcheck disable=SC2086 # the options are words
            ./target/release/bsp2vdg -quiet --json $opts -rl "$rl" -o "$TMP/$name.vdg" "$m" > "$TMP/c.json"
            ./target/release/vdgview check --json --samples "$N" "$m" "$TMP/$name.vdg" > "$TMP/k.json" || true
            python3 - "$name" "$rl" "$TMP/c.json" "$TMP/k.json" "$opts" >> "$table" <<'PY'
import json, sys
name, rl, c, k, opts = sys.argv[1], sys.argv[2], json.load(open(sys.argv[3])), json.load(open(sys.argv[4])), sys.argv[5]
before = c.get("reduce_vertices_before") or c["vertices"]
after = c.get("reduced_vertices") or before
print(name, rl, "%.5f" % (after / max(before, 1)), "n/a" if k["walkable_coverage"] is None else "%.5f" % k["walkable_coverage"], "%.5f" % k["coverage"],
      c.get("reduce_stop_reason") or "-", "%.5f" % k["visible_fn_inside"], after, " ".join(opts.split()) or "-", sep="\t")
PY
            tail -n1 "$table"
        done
    done
done
./target/release/reduction_curve "$table" "$png"
./target/release/fn_vertices "$table" "${png%.png}-vertices.png"
echo "wrote $table, $png and ${png%.png}-vertices.png"
