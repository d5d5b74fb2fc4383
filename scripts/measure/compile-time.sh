#!/usr/bin/env bash
# The whole-pipeline time target (≤ 30 s and ≤ 2 GiB for a map of
# about 180 000 samples on this 2-core machine): compiles one map RUNS times
# and prints per run the sample count, the seconds per stage, the CPU seconds
# (user + system: less noisy than the wall clock on a shared machine) and the
# peak memory, then the median of each column. This machine is noisy: compare
# medians, and builds only against each other in the same run (BINS).
#
#   scripts/compile-time.sh [-runs 5] [-sd 18.5] [-threads N] MAP.bsp
#   BINS="old=/path/to/bsp2vdg new=target/release/bsp2vdg" scripts/compile-time.sh MAP.bsp
#
# de_cbble (../shared/testmaps/goldsrc/nonfree) at -sd 18.5 is a map of about that size.
# With BINS the builds run alternately, one run of each per round.
set -euo pipefail
cd "$(dirname "$(readlink -f "$0")")/../.."
RUNS=5
SD=18.5
THREADS=()
while [[ $# -gt 0 && "$1" == -* ]]; do
    case "$1" in
        -runs) RUNS="$2"; shift 2 ;;
        -sd) SD="$2"; shift 2 ;;
        -threads) THREADS=(-threads "$2"); shift 2 ;;
        *) echo "unknown option $1" >&2; exit 2 ;;
    esac
done
[[ $# -eq 1 ]] || { echo "usage: $0 [-runs N] [-sd M] [-threads N] MAP.bsp" >&2; exit 2; }
if [[ -z "${BINS:-}" ]]; then
    cargo build --release -q -p bsp2vdg
    BINS="bsp2vdg=$PWD/target/release/bsp2vdg"
fi
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT
cp "$1" "$TMP/map.bsp"
for round in $(seq 1 "$RUNS"); do
    for entry in $BINS; do
        name="${entry%%=*}"
        bin="${entry#*=}"
        /usr/bin/time -f '%M %U %S' -o "$TMP/mem" "$bin" "${THREADS[@]}" -quiet --json -sd "$SD" \
            -o "$TMP/out.vdg" "$TMP/map.bsp" > "$TMP/$name.$round.json"
        echo "$(cat "$TMP/mem")" > "$TMP/$name.$round.mem"
    done
done
python3 - "$TMP" "$RUNS" $BINS <<'PY'
import json, statistics, sys
tmp, runs, bins = sys.argv[1], int(sys.argv[2]), [b.split("=")[0] for b in sys.argv[3:]]
stages = ["sample", "delaunay", "voronoi", "guard", "reduce", "wall_raise", "check", "total"]
print("build\trun\tsamples\t" + "\t".join(stages) + "\tcpu_s\tpeak_MiB")
for name in bins:
    rows = []
    for r in range(1, runs + 1):
        d = json.load(open(f"{tmp}/{name}.{r}.json"))
        kib, user, system = open(f"{tmp}/{name}.{r}.mem").read().split()[-3:]
        row = [d["seconds"].get(k, 0.0) for k in stages] + [float(user) + float(system), int(kib) / 1024]
        rows.append(row)
        print(name, r, d["samples"], *("%.2f" % x for x in row[:-1]), "%.0f" % row[-1], sep="\t")
    med = [statistics.median(c) for c in zip(*rows)]
    print(name, "median", d["samples"], *("%.2f" % x for x in med[:-1]), "%.0f" % med[-1], sep="\t")
PY
