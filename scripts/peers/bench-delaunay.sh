#!/usr/bin/env bash
# Benchmark of the 3D Delaunay triangulator (bsp2vdg::delaunay) against CGAL's sequential
# Delaunay_triangulation_3 and qhull's qdelaunay, measured in the same run.
#
# Generates reproducible point files in qhull's text format (uniform cube 100k / 1M; a box
# level's wall samples on the 24-unit grid, ~112k and ~475k points, exact and with 1e-3
# jitter; the samples of a real map when the bsp2vdg CLI can produce them), then times
#   ours:  target/release/examples/tetrahedralize FILE   (JSON: seconds = triangulation only)
#   CGAL:  scripts/peers/cgal/cgal_delaunay.cpp built with g++ -O3 -DNDEBUG (JSON like ours; range
#          insert with CGAL's spatial sort, Epick kernel); needs libcgal-dev, installed with
#          apt-get when possible, else the column is skipped
#   qhull: qdelaunay Qt i < FILE
# with /usr/bin/time (wall seconds of the whole process, peak RSS), and prints a table of
# medians. Environment:
#   RUNS=3            runs per measurement of ours and of CGAL (median reported)
#   SKIP_CGAL=1       no CGAL column
#   SKIP_QHULL=1      no qhull column (qhull needs minutes on the large inputs)
#   QHULL_RUNS=3      runs per qhull measurement
#   QHULL_RUNS_LARGE  runs per qhull measurement above 200k points (default QHULL_RUNS;
#                     qhull needs ~5 minutes per run on the 475k wall samples)
#   QHULL_TIMEOUT=900 seconds before a qhull run is abandoned
#   ONLY=regex        only inputs whose name matches
#   OUT=DIR           where point files are kept (default target/delaunay-bench)
set -euo pipefail
cd "$(dirname "$(readlink -f "$0")")/../.."
OUT=${OUT:-target/delaunay-bench}
mkdir -p "$OUT"

echo "building the tetrahedralize example (release)..." >&2
nice cargo build --release -q -p bsp2vdg --example tetrahedralize

if [ "${SKIP_CGAL:-0}" != 1 ]; then
    if [ ! -f /usr/include/CGAL/Delaunay_triangulation_3.h ]; then
        echo "CGAL headers not found: trying apt-get install libcgal-dev" >&2
        (apt-get update -qq && apt-get install -y -qq libcgal-dev) >/dev/null 2>&1 ||
            echo "could not install libcgal-dev: the CGAL column will be skipped" >&2
    fi
    if [ -f /usr/include/CGAL/Delaunay_triangulation_3.h ]; then
        if [ ! "$OUT/cgal_delaunay" -nt scripts/peers/cgal/cgal_delaunay.cpp ]; then
            echo "building the CGAL peer (g++ -O3 -DNDEBUG)..." >&2
            nice g++ -O3 -DNDEBUG -o "$OUT/cgal_delaunay" scripts/peers/cgal/cgal_delaunay.cpp \
                -lgmp -lmpfr || echo "could not build the CGAL peer: column skipped" >&2
        fi
        if [ -x "$OUT/cgal_delaunay" ]; then export CGAL_BIN="$OUT/cgal_delaunay"; fi
    fi
fi

if [ "${SKIP_QHULL:-0}" != 1 ] && ! command -v qdelaunay >/dev/null 2>&1; then
    echo "qdelaunay not found: trying apt-get install qhull-bin" >&2
    (apt-get update -qq && apt-get install -y -qq qhull-bin) >/dev/null 2>&1 ||
        echo "could not install qhull-bin: the qhull column will be skipped" >&2
fi

gen() { # name, generator args...
    local name=$1
    shift
    [ -s "$OUT/$name.txt" ] || python3 scripts/peers/delaunay-genpoints.py "$@" "$OUT/$name.txt"
}
gen uniform-100k uniform 100000
gen uniform-1M uniform 1000000
gen walls-112k boxlevel 11 10 1 0
gen walls-112k-jitter boxlevel 11 10 1 0.001
gen walls-475k boxlevel 22 21 1 0
gen walls-475k-jitter boxlevel 22 21 1 0.001

# The shared maps live beside the repository (SHARED overrides the folder).
MAP=${SHARED:-../shared}/testmaps/goldsrc/nonfree/bspview-cstrike-de_dust2.bsp
if [ ! -s "$OUT/de_dust2.samples.txt" ]; then
    if [ -f "$MAP" ] && cargo run --release -q -p bsp2vdg -- --stop-after samples -savesamples \
        --samples-format qhull -o "$OUT/de_dust2.vdg" "$MAP" >/dev/null 2>"$OUT/de_dust2.err"; then
        echo "real map samples written" >&2
    else
        echo "skipping the real map: the bsp2vdg CLI could not write its samples ($(head -c 200 "$OUT/de_dust2.err" 2>/dev/null))" >&2
    fi
fi
if [ -s "$OUT/de_dust2.samples.txt" ]; then
    cp "$OUT/de_dust2.samples.txt" "$OUT/de_dust2.txt"
fi

# Time a private copy, so rebuilding during a long run does not change the binary.
cp target/release/examples/tetrahedralize "$OUT/tetrahedralize"
OURS="$OUT/tetrahedralize" exec python3 scripts/peers/delaunay-bench.py "$OUT"
