#!/usr/bin/env bash
# Runs every reader's coverage-guided fuzz target (libFuzzer through cargo-fuzz),
# one after the other, each for a given time or number of executions, and prints
# a table: target, executions, coverage (libFuzzer's cov and ft), corpus size,
# crashes.
#
#   scripts/fuzz.sh SECONDS [TARGET...]      # e.g. scripts/fuzz.sh 600
#   RUNS=10000000 scripts/fuzz.sh 0 bsp      # a fixed number of executions instead
#
# TARGET names (default: all):
#   bsp             bsp/fuzz bsp_reader: the map reader of every game (GoldSrc,
#                   Quake BSP29/BSP2/2PSB, Quake 2, Quake 3) and every query on
#                   what it accepts
#   compile         bsp2vdg/fuzz bsp_reader: the same, then the compiler's sampling
#   vdg             vdgformat/fuzz reader: the .vdg reader and every graph query
#   camera          vdgformat/fuzz camera_toml: the camera parameters' TOML
#   nav             navmesh/fuzz nav_reader: Counter-Strike bot nav meshes
#   tiling          flowtile-bake/fuzz baked_tiling: baked flow tile files
#   problem         flowtile-bake/fuzz problem_toml: flow tile problem specs
#   dem             demo/fuzz demo_reader: GoldSrc demos (.dem), when that crate exists
#                   (seed it with SEEDS=../shared/testmaps/demos)
#
# Needs cargo-fuzz (`cargo install cargo-fuzz`). On a stable toolchain the
# nightly flags cargo-fuzz passes are allowed with RUSTC_BOOTSTRAP=1 (set here).
# Each target keeps its corpus in <crate>/fuzz/corpus/<target> (created and
# seeded from the repository's test data and <crate>/fuzz/seeds on every run;
# SEEDS=DIR adds the small files of DIR with the seeds' extension, e.g.
# SEEDS=../shared/testmaps; the corpora are not kept in git, the seeds are). Crashes land in <crate>/fuzz/artifacts/<target>.
# NICE (default 10) and JOBS (default 1) keep it polite on a shared machine;
# RSS_MB (default 2048) is the memory a single input may use before libFuzzer
# calls it a crash; TIMEOUT (default 10 s) the time; MAX_LEN overrides each
# target's input size cap.
#
# Exit 1 when any target found a crash, a hang or an out-of-memory input.
set -euo pipefail
cd "$(dirname "$0")/.."
[ $# -ge 1 ] || { sed -n 2,30p "$0" >&2; exit 2; }
SECONDS_EACH=$1
shift
command -v cargo-fuzz >/dev/null || { echo "cargo-fuzz is not installed (cargo install cargo-fuzz)" >&2; exit 2; }
export RUSTC_BOOTSTRAP=1
NICE=${NICE:-10}
JOBS=${JOBS:-1}
RSS_MB=${RSS_MB:-2048}
TIMEOUT=${TIMEOUT:-10}
LOGS=${LOGS:-target/fuzz-logs}
mkdir -p "$LOGS"

# name crate-dir fuzz-target max-input-bytes seed-globs...
# (the input cap keeps each execution cheap: the seeds are small maps and files)
declare -A CRATE TARGET SEED MAXLEN
add() { CRATE[$1]=$2; TARGET[$1]=$3; MAXLEN[$1]=$4; SEED[$1]=$5; }
add bsp      bsp            bsp_reader   65536 "testdata/maps/*.bsp bsp/fuzz/seeds/bsp_reader/*.bsp"
add compile  bsp2vdg        bsp_reader   65536 "testdata/maps/*.bsp bsp/fuzz/seeds/bsp_reader/*.bsp"
add vdg      vdgformat      reader       16384 "vdgformat/fuzz/seeds/reader/*.vdg"
add camera   vdgformat      camera_toml  4096  "vdgformat/fuzz/seeds/camera_toml/*.toml"
add nav      navmesh        nav_reader   4096  "navmesh/fuzz/seeds/nav_reader/*.nav"
add tiling   flowtile-bake  baked_tiling 8192  "flowtile-bake/fuzz/seeds/baked_tiling/*.ftb"
add problem  flowtile-bake  problem_toml 4096  "testdata/flowtiles/*.toml"
ALL="bsp compile vdg camera nav tiling problem"
# The GoldSrc demo reader's target, if its crate is there.
if [ -f demo/fuzz/fuzz_targets/demo_reader.rs ]; then
    add dem demo demo_reader 65536 "demo/fuzz/seeds/demo_reader/*.dem demo/tests/data/*.dem testdata/demos/*.dem"
    ALL="$ALL dem"
fi
[ $# -gt 0 ] && ALL="$*"

status=0
rows=()
for name in $ALL; do
    [ -n "${CRATE[$name]:-}" ] || { echo "unknown target $name (known: ${!CRATE[*]})" >&2; exit 2; }
    crate=${CRATE[$name]}
    target=${TARGET[$name]}
    corpus="$crate/fuzz/corpus/$target"
    mkdir -p "$corpus" "$crate/fuzz/artifacts/$target"
    # The seeds join the corpus on every run (a seed added later is not missed).
    # shellcheck disable=SC2086
    for f in ${SEED[$name]}; do [ -f "$f" ] && cp -n "$f" "$corpus/"; done
    extra=()
    if [ -n "${SEEDS:-}" ]; then
        seeds="$LOGS/seeds-$name"
        rm -rf "$seeds"
        mkdir -p "$seeds"
        # Small files only: libFuzzer mutates a seed as a whole.
        find "$SEEDS" -type f -size -1M -name "*.${SEED[$name]##*.}" -exec cp {} "$seeds/" \; 2>/dev/null || true
        extra=("$PWD/$seeds")
    fi
    limit=(-max_total_time="$SECONDS_EACH" -max_len="${MAX_LEN:-${MAXLEN[$name]}}")
    [ -n "${RUNS:-}" ] && limit=(-runs="$RUNS" -max_len="${MAX_LEN:-${MAXLEN[$name]}}")
    # One job runs in this process (-jobs=1 would fork a worker logging elsewhere).
    jobs=()
    [ "$JOBS" -gt 1 ] && jobs=(-jobs="$JOBS" -workers="$JOBS")
    log="$LOGS/$name.log"
    echo "== $name ($crate/fuzz $target) -> $log"
    set +e
    (cd "$crate/fuzz" && nice -n "$NICE" cargo fuzz run -s none "$target" \
        "corpus/$target" "${extra[@]}" -- \
        "${limit[@]}" "${jobs[@]}" -rss_limit_mb="$RSS_MB" \
        -malloc_limit_mb="$RSS_MB" -timeout="$TIMEOUT" -print_final_stats=1 \
        -artifact_prefix="artifacts/$target/") >"$log" 2>&1
    rc=$?
    set -e
    # With -jobs the workers log to fuzz-N.log in the crate's fuzz folder.
    if [ "$JOBS" -gt 1 ]; then cat "$crate/fuzz"/fuzz-*.log >>"$log" 2>/dev/null; rm -f "$crate/fuzz"/fuzz-*.log; fi
    execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | awk '{s+=$2} END {print s+0}')
    last=$(grep -E '#[0-9]+' "$log" | grep -E 'cov: [0-9]+' | tail -1)
    cov=$(sed -nE 's/.*cov: ([0-9]+).*/\1/p' <<<"$last")
    ft=$(sed -nE 's/.*ft: ([0-9]+).*/\1/p' <<<"$last")
    files=$(find "$corpus" -type f | wc -l)
    crashes=$(find "$crate/fuzz/artifacts/$target" -type f | wc -l)
    verdict=ok
    if [ $rc -ne 0 ]; then verdict="FAILED (exit $rc, see $log)"; status=1; fi
    rows+=("$(printf '%-8s %-14s %-13s %12s %6s %7s %7s %7s  %s' "$name" "$crate" "$target" "$execs" "${cov:-?}" "${ft:-?}" "$files" "$crashes" "$verdict")")
done

printf '%-8s %-14s %-13s %12s %6s %7s %7s %7s  %s\n' target crate fuzz_target executions cov ft corpus crashes verdict
printf '%s\n' "${rows[@]}"
exit $status
