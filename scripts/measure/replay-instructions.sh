#!/usr/bin/env bash
# Instructions per camera update in a camera replay: the VDG camera's cost on the routes the
# replay measures (spawn, nav or demo routes), free of the machine's noise. Runs
# `vdgview replay MAP.bsp MAP.vdg --camera vdg ...` under callgrind, cut into one profile before
# and one after every `Camera::update` (the replay's own BSP work between updates falls into the
# parts in between and is left out), and prints the median, p90, p99, max and mean instructions
# over the updates.
#   scripts/measure/replay-instructions.sh MAP.bsp MAP.vdg [replay options, e.g. --dt 1/30 --seed 2 --routes nav:MAP.nav]
#   VDGVIEW=/path/to/vdgview scripts/measure/replay-instructions.sh ...   (compare two builds)
# Needs valgrind; a set of routes takes a minute or a few. Dumps go to a temporary folder,
# removed after.
set -euo pipefail
cd "$(dirname "$(readlink -f "$0")")/../.."
if [ $# -lt 2 ]; then
    echo "usage: scripts/measure/replay-instructions.sh MAP.bsp MAP.vdg [vdgview replay options]" >&2
    exit 2
fi
command -v valgrind >/dev/null || { echo "replay-instructions: valgrind not found" >&2; exit 1; }
viewer=${VDGVIEW:-}
if [ -z "$viewer" ]; then
    cargo build --release -q -p vdgview
    viewer=target/release/vdgview
fi
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
valgrind --tool=callgrind --callgrind-out-file="$out/cg.out" \
    --dump-before='*::Camera::update' --dump-after='*::Camera::update' \
    --dump-instr=no --collect-jumps=no "$viewer" replay "$@" --camera vdg >"$out/replay.txt" 2>"$out/valgrind.log" ||
    { tail -5 "$out/valgrind.log" >&2; exit 1; }
python3 - "$out" <<'PY'
import glob, sys
# A dump made after Camera::update returns holds exactly that update.
x = []
for path in glob.glob(sys.argv[1] + "/cg.out.*"):
    total, trigger = None, ""
    with open(path) as f:
        for line in f:
            if line.startswith("desc: Trigger:"):
                trigger = line
            elif line.startswith("totals:"):
                total = int(line.split()[1])
    if "--dump-after" in trigger and total is not None:
        x.append(total)
if not x:
    sys.exit("replay-instructions: no updates measured (is Camera::update inlined?)")
x.sort()
q = lambda f: x[round((len(x) - 1) * f)]
print(f"updates {len(x)}  instructions per update: median {q(0.5)}  p90 {q(0.9)}  "
      f"p99 {q(0.99)}  max {x[-1]}  mean {sum(x) / len(x):.0f}")
PY
