#!/usr/bin/env bash
# Thesis table 7.1 columns for the reduction (issue 5): per map, samples,
# inner nodes/faces, reduced nodes/faces, .vdg bytes, seconds per stage,
# peak memory (GNU time) and the stop reason.
#
#   scripts/reduce-measure.sh [-sd 24] [-rl 0.025] MAP.bsp...
#
# Builds the release binary, compiles each map once into a temp folder
# (the log goes beside the map copy) and prints one tab-separated row per map.
set -euo pipefail
cd "$(dirname "$0")/.."
SD=24
RL=0.025
while [[ $# -gt 0 && "$1" == -* ]]; do
    case "$1" in
        -sd) SD="$2"; shift 2 ;;
        -rl) RL="$2"; shift 2 ;;
        *) echo "unknown option $1" >&2; exit 2 ;;
    esac
done
cargo build --release -q -p bsp2vdg
BIN="$PWD/target/release/bsp2vdg"
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT
printf 'map\tsamples\tinner_nodes\tinner_faces\treduced_nodes\treduced_faces\tbytes\tsample_s\tdelaunay_s\tvoronoi_s\treduce_s\ttotal_s\tpeak_MiB\tstop\n'
for map in "$@"; do
    name="$(basename "$map" .bsp)"
    cp "$map" "$TMP/$name.bsp"
    /usr/bin/time -f '%M' -o "$TMP/$name.mem" \
        "$BIN" -quiet --json -sd "$SD" -rl "$RL" -o "$TMP/$name.vdg" "$TMP/$name.bsp" > "$TMP/$name.json"
    python3 - "$TMP/$name.json" "$TMP/$name.mem" "$name" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
mem = int(open(sys.argv[2]).read().split()[-1]) / 1024
s = d["seconds"]
row = [sys.argv[3], d["samples"], d["graph_vertices"], d["graph_faces"],
       d["reduced_vertices"], d["reduced_faces"], d["bytes"],
       *("%.2f" % s.get(k, 0.0) for k in ("sample", "delaunay", "voronoi", "reduce", "total")),
       "%.0f" % mem, d["reduce_stop_reason"]]
print("\t".join(str(x) for x in row))
PY
    rm -f "$TMP/$name".*
done
