#!/usr/bin/env bash
# Thesis table 7.1 columns for the reduction: per map and
# reduction limit, samples, inner nodes/faces, reduced nodes/faces, .vdg
# bytes, seconds per stage, peak memory (GNU time), the stop reason and,
# with -check, coverage, walkable coverage (player origin, head), visible
# false negatives inside the volume, leak, and the false negatives on the
# camera's sight lines (vis_fn_camera) from `vdgview check` (the figures
# against the unreduced graph are the row with -rl 1.0).
#
#   scripts/reduce-measure.sh [-sd 24] [-rl 0.025[,0.05,...]] [-check] [-threads N] MAP.bsp...
#
# Builds the release binaries, compiles each map once per limit into a temp
# folder (the log goes beside the map copy) and prints one tab-separated row
# per map and limit. Set BIN_DIR to use already built binaries.
set -euo pipefail
cd "$(dirname "$(readlink -f "$0")")/../.."
SD=24
RL=0.025
CHECK=0
THREADS=()
while [[ $# -gt 0 && "$1" == -* ]]; do
    case "$1" in
        -sd) SD="$2"; shift 2 ;;
        -rl) RL="$2"; shift 2 ;;
        -check) CHECK=1; shift ;;
        -threads) THREADS=(-threads "$2"); shift 2 ;;
        *) echo "unknown option $1" >&2; exit 2 ;;
    esac
done
if [[ -z "${BIN_DIR:-}" ]]; then
    cargo build --release -q -p bsp2vdg -p vdgview
    BIN_DIR="$PWD/target/release"
fi
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT
printf 'map\trl\tsamples\tinner_nodes\tinner_faces\treduced_nodes\treduced_faces\tratio\tbytes\tsample_s\tdelaunay_s\tvoronoi_s\tguard_s\treduce_s\tcheck_s\ttotal_s\tpeak_MiB\tstop\tcoverage\twalkable\twalkable_head\tvis_fn_inside\tvis_fn_query\tleak\tvis_fn_camera\n'
for map in "$@"; do
    name="$(basename "$map" .bsp)"
    cp "$map" "$TMP/$name.bsp"
    for rl in ${RL//,/ }; do
        /usr/bin/time -f '%M' -o "$TMP/$name.mem" \
            "$BIN_DIR/bsp2vdg" "${THREADS[@]}" -quiet --json -sd "$SD" -rl "$rl" -o "$TMP/$name.vdg" "$TMP/$name.bsp" > "$TMP/$name.json"
        if [[ $CHECK == 1 ]]; then
            "$BIN_DIR/vdgview" check "$TMP/$name.bsp" "$TMP/$name.vdg" --samples 100000 --json > "$TMP/$name.check" || true
        else
            echo '{}' > "$TMP/$name.check"
        fi
        python3 - "$TMP/$name.json" "$TMP/$name.mem" "$name" "$rl" "$TMP/$name.check" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
mem = int(open(sys.argv[2]).read().split()[-1]) / 1024
c = json.load(open(sys.argv[5]))
s = d["seconds"]
before = d.get("reduce_vertices_before") or d["vertices"]
after = d.get("reduced_vertices") or before
row = [sys.argv[3], sys.argv[4], d["samples"], before, d.get("reduce_faces_before") or d["vdg_faces"],
       after, d.get("reduced_faces") or d["vdg_faces"], "%.4f" % (after / max(before, 1)), d["bytes"],
       *("%.2f" % s.get(k, 0.0) for k in ("sample", "delaunay", "voronoi", "guard", "reduce", "check", "total")),
       "%.0f" % mem, d.get("reduce_stop_reason") or "-",
       "%.3f" % c["coverage"] if "coverage" in c else "-",
       *("%.4f" % c[k] if c.get(k) is not None else ("n/a" if k in c else "-")
         for k in ("walkable_coverage", "walkable_coverage_head", "visible_fn_inside", "visible_fn_query")),
       "%.4f" % c["leak"] if "leak" in c else "-",
       "%.4f" % c["visible_fn_camera"] if c.get("visible_fn_camera") is not None else ("n/a" if "visible_fn_camera" in c else "-")]
print("\t".join(str(x) for x in row), flush=True)
if d.get("reduce_refusals"):
    print("#", sys.argv[3], sys.argv[4], "refusals:", json.dumps(d["reduce_refusals"]), flush=True)
PY
    done
    rm -f "$TMP/$name".*
done
