#!/usr/bin/env bash
# Maps per minute of scripts/bake.py (Dask.distributed, local cluster on 127.0.0.1) with 1
# and 2 worker processes on the shared maps, alternating the worker counts RUNS times
# (the machine is noisy), each run compiling everything (--no-cache), -threads 1 per map.
#
#   scripts/bake-measure.sh [MAPS...]      default: ../shared/testmaps free GoldSrc and Quake maps
#   RUNS=3 OPTS="-sd 24" scripts/bake-measure.sh
set -euo pipefail
cd "$(dirname "$(readlink -f "$0")")/../.."
SHARED=${SHARED:-../shared}
RUNS=${RUNS:-2}
if [ $# -gt 0 ]; then maps=("$@"); else
    shopt -s nullglob
    maps=("$SHARED"/testmaps/goldsrc/*.bsp "$SHARED"/testmaps/quake1/*.bsp)
fi
[ ${#maps[@]} -gt 0 ] || { echo "skipped: no maps (is $SHARED/testmaps there?)"; exit 0; }
cargo build --release -q -p bsp2vdg
OUT=target/bake-measure
for r in $(seq "$RUNS"); do
    for w in 1 2; do
        line=$(python3 scripts/bake.py --workers "$w" --no-cache --out "$OUT/out" --cache "$OUT/cache" \
            "${maps[@]}" -- ${OPTS:-} | tail -1) || true
        echo "run $r workers $w: $line"
    done
done
