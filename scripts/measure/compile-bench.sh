#!/usr/bin/env bash
# Whole-compile speed of two builds of bsp2vdg, old and new alternating: per
# map, RUNS rounds of one compile with each build (the order flips every
# round, so neither build always runs on a warmer cache), then per build the
# median seconds of every stage the compile's --json reports, the median
# CPU seconds (user + system, steadier than the wall clock on a shared
# machine) and the median peak memory, and the ratio old/new of each median
# (above 1: the new build is faster). Both builds must write the same graph
# for a speed comparison to mean what it says: the script says whether they
# do: "same" (the same bytes), "same-graph" (the files differ, but `vdgview
# info` says the same of both but for the build identity `tool.build`, which
# every build records), or "differ" (a build that changes the graph on
# purpose). `vdgview` is taken from VDGVIEW, else from beside NEW_BIN.
#
#   scripts/measure/compile-bench.sh [-runs 3] [-threads N] [-maps "NAME ..."] OLD_BIN NEW_BIN
#
# The maps (from ../shared/testmaps; skipped with a message when absent) are
# those of about 100 000 wall samples or more: de_dust2, de_cbble at -sd 18.5
# (about the thesis' crossfire in size), c1a0, oasago2, lq_e0m2 and the
# Quake 2 lq_e0m2. -maps picks some of them by these names: de_dust2
# de_cbble c1a0 oasago2 lq_e0m2 q2_e0m2. Compiles run under `nice -n 5`.
set -euo pipefail
cd "$(dirname "$(readlink -f "$0")")/../.."
RUNS=3
THREADS=()
PICK="de_dust2 de_cbble c1a0 oasago2 lq_e0m2 q2_e0m2"
while [[ $# -gt 0 && "$1" == -* ]]; do
    case "$1" in
        -runs) RUNS="$2"; shift 2 ;;
        -threads) THREADS=(-threads "$2"); shift 2 ;;
        -maps) PICK="$2"; shift 2 ;;
        *) echo "unknown option $1" >&2; exit 2 ;;
    esac
done
[[ $# -eq 2 ]] || { echo "usage: $0 [-runs N] [-threads N] [-maps \"NAME ...\"] OLD_BIN NEW_BIN" >&2; exit 2; }
OLD="$(readlink -f "$1")"
NEW="$(readlink -f "$2")"
for b in "$OLD" "$NEW"; do
    [[ -x "$b" ]] || { echo "not an executable: $b" >&2; exit 2; }
done
VDGVIEW="${VDGVIEW:-$(dirname "$NEW")/vdgview}"
MAPS=../shared/testmaps
if [[ ! -d "$MAPS" ]]; then
    echo "skipped: $MAPS is absent"
    exit 0
fi
# name, path under $MAPS, extra options
declare -A PATHS=(
    [de_dust2]=goldsrc/nonfree/bspview-cstrike-de_dust2.bsp
    [de_cbble]=goldsrc/nonfree/bspview-cstrike-de_cbble.bsp
    [c1a0]=goldsrc/nonfree/bspview-halflife_c1a0.bsp
    [oasago2]=quake3/openarena-oasago2.bsp
    [lq_e0m2]=quake1/lq_e0m2.bsp
    [q2_e0m2]=quake2/lq_e0m2-quake2.bsp
)
declare -A OPTS=([de_cbble]="-sd 18.5")
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT
for name in $PICK; do
    rel="${PATHS[$name]:-}"
    [[ -n "$rel" ]] || { echo "unknown map name $name" >&2; exit 2; }
    if [[ ! -f "$MAPS/$rel" ]]; then
        echo "skipped $name: $MAPS/$rel is absent"
        continue
    fi
    mkdir -p "$TMP/$name"
    cp "$MAPS/$rel" "$TMP/$name/map.bsp"
    # shellcheck disable=SC2206
    extra=(${OPTS[$name]:-})
    for round in $(seq 1 "$RUNS"); do
        order="old new"
        (( round % 2 == 0 )) && order="new old"
        for which in $order; do
            bin="$OLD"
            [[ $which == new ]] && bin="$NEW"
            /usr/bin/time -f '%M %U %S' -o "$TMP/$name/$which.$round.time" \
                nice -n 5 "$bin" "${THREADS[@]}" -quiet --json "${extra[@]}" \
                -o "$TMP/$name/$which.vdg" "$TMP/$name/map.bsp" > "$TMP/$name/$which.$round.json"
        done
    done
    if cmp -s "$TMP/$name/old.vdg" "$TMP/$name/new.vdg"; then
        echo same > "$TMP/$name/identical"
    elif [[ -x "$VDGVIEW" ]] && diff -q \
        <("$VDGVIEW" info "$TMP/$name/old.vdg" | grep -v 'tool\.build') \
        <("$VDGVIEW" info "$TMP/$name/new.vdg" | grep -v 'tool\.build') > /dev/null; then
        echo same-graph > "$TMP/$name/identical"
    else
        echo differ > "$TMP/$name/identical"
    fi
done
python3 - "$TMP" "$RUNS" $PICK <<'PY'
import json, os, statistics, sys
tmp, runs, names = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
stages = ["sample", "delaunay", "voronoi", "guard", "reduce", "wall_raise",
          "check", "corner_check", "write", "total"]
print("map\tbuild\tsamples\tfaces\tbytes\t" + "\t".join(stages) + "\tcpu_s\tpeak_MiB")
for name in names:
    d = os.path.join(tmp, name)
    if not os.path.exists(os.path.join(d, "identical")):
        continue
    med = {}
    for which in ("old", "new"):
        rows = []
        for r in range(1, runs + 1):
            j = json.load(open(f"{d}/{which}.{r}.json"))
            kib, user, system = open(f"{d}/{which}.{r}.time").read().split()[-3:]
            rows.append([j["seconds"].get(k, 0.0) for k in stages]
                        + [float(user) + float(system), int(kib) / 1024])
        med[which] = [statistics.median(c) for c in zip(*rows)]
        print(name, which, j["samples"], j["vdg_faces"], j["bytes"],
              *("%.2f" % x for x in med[which][:-1]), "%.0f" % med[which][-1], sep="\t")
    ratio = [o / n if n > 0 else float("nan") for o, n in zip(med["old"], med["new"])]
    print(name, "old/new", "-", "-", open(f"{d}/identical").read().strip(),
          *("%.2f" % x for x in ratio), sep="\t")
PY
