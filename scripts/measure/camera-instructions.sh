#!/usr/bin/env bash
# Instructions per camera update: the most stable cost figure on a busy machine.
# Runs camera_bench under callgrind, cut into one profile per update (the bench calls the
# never-inlined timed_update and update_done around each one), and prints the median, p90,
# p99, max and mean instructions over the updates after the first second of warm-up.
#   scripts/camera-instructions.sh FILE.vdg [camera_bench options, e.g. --frames 2400 --params CAM.toml]
#   BENCH=/path/to/camera_bench scripts/camera-instructions.sh ...   (compare two builds)
# Needs valgrind; about a minute per 1000 frames. Dumps go to a temporary folder, removed after.
set -euo pipefail
cd "$(dirname "$(readlink -f "$0")")/../.."
if [ $# -lt 1 ]; then
    echo "usage: scripts/camera-instructions.sh FILE.vdg [camera_bench options]" >&2
    exit 2
fi
command -v valgrind >/dev/null || { echo "camera-instructions: valgrind not found" >&2; exit 1; }
bench=${BENCH:-}
if [ -z "$bench" ]; then
    cargo build --release -q -p vdgformat --example camera_bench
    bench=target/release/examples/camera_bench
fi
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
valgrind --tool=callgrind --callgrind-out-file="$out/cg.out" \
    --dump-before='*timed_update*' --dump-before='*update_done*' \
    --dump-instr=no --collect-jumps=no "$bench" "$@" >"$out/bench.txt" 2>"$out/valgrind.log" ||
    { tail -5 "$out/valgrind.log" >&2; exit 1; }
python3 - "$out" <<'PY'
import glob, sys
# Each dump made before update_done holds one update; the first second (60 updates at the
# bench's default dt) is warm-up, as in the bench's own figures.
updates = []
for path in glob.glob(sys.argv[1] + "/cg.out.*"):
    part, total, trigger = None, None, ""
    with open(path) as f:
        for line in f:
            if line.startswith("part:"):
                part = int(line.split()[1])
            elif line.startswith("desc: Trigger:"):
                trigger = line
            elif line.startswith("totals:"):
                total = int(line.split()[1])
    if "update_done" in trigger and part is not None and total is not None:
        updates.append((part, total))
updates.sort()
x = sorted(t for _, t in updates[60:])
if not x:
    sys.exit("camera-instructions: no updates measured")
q = lambda f: x[round((len(x) - 1) * f)]
print(f"updates {len(x)}  instructions per update: median {q(0.5)}  p90 {q(0.9)}  "
      f"p99 {q(0.99)}  max {x[-1]}  mean {sum(x) / len(x):.0f}")
PY
