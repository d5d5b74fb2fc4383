#!/usr/bin/env bash
# Foundation acceptance figures on the real maps in ../shared/testmaps: per map, faces,
# sampled faces, samples at -sd 24, read/sample seconds, player spawns in free space,
# samples moved 1 unit in front of / behind their face that the BSP calls free / blocked
# (all samples, and interior samples more than 1 unit from the face's edges), and the
# largest distance of 10^5 random face points to their nearest sample (must be <= m).
set -euo pipefail
cd "$(dirname "$(readlink -f "$0")")/../.."
maps=../shared/testmaps
if [ ! -d "$maps" ]; then echo "skipped: $maps is absent"; exit 0; fi
cargo build --release -q -p lab --bin foundation_report
shopt -s nullglob
./target/release/foundation_report -sd "${SD:-24}" -n "${N:-100000}" \
  "$maps"/goldsrc/*.bsp "$maps"/goldsrc/nonfree/*.bsp "$maps"/quake1/*.bsp "$maps"/quake1/nonfree/*.bsp
