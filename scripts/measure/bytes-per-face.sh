#!/usr/bin/env bash
# Bytes per face of the .vdg files one build of bsp2vdg writes (issue 41, item 3): compiles
# every map at the default options (or OPTS) and prints one TSV row per map: vertices, faces,
# the file's size and size / faces, and the compile's seconds and reduction counters from its
# `--json`. The graphs stay in OUT_DIR (for `vdgview check` or a before/after comparison).
#   scripts/measure/bytes-per-face.sh BSP2VDG_BIN OUT_DIR [MAP.bsp ...]
# Without maps: every GoldSrc, Quake 1, 2 and 3 map in ../shared/testmaps (nonfree too).
#   THREADS=1 (default) OPTS="-sd 18.5" NICE=10
set -euo pipefail
cd "$(dirname "$(readlink -f "$0")")/../.."
if [ $# -lt 2 ]; then
  echo "usage: scripts/measure/bytes-per-face.sh BSP2VDG_BIN OUT_DIR [MAP.bsp ...]" >&2
  exit 2
fi
bin=$1 out=$2; shift 2
[ -x "$bin" ] || { echo "bytes-per-face: $bin is not an executable" >&2; exit 2; }
mkdir -p "$out"
shopt -s nullglob
maps=("$@")
if [ ${#maps[@]} -eq 0 ]; then
  maps=(../shared/testmaps/goldsrc/*.bsp ../shared/testmaps/goldsrc/nonfree/*.bsp
        ../shared/testmaps/goldsrc/nonfree/cs/*.bsp
        ../shared/testmaps/quake1/*.bsp ../shared/testmaps/quake1/nonfree/*.bsp
        ../shared/testmaps/quake2/*.bsp ../shared/testmaps/quake3/*.bsp)
fi
printf 'map\tvertices\tfaces\tbytes\tbytes_per_face\tseconds\treduce_s\tguard_s\traise_s\n'
for m in "${maps[@]}"; do
  name=$(basename "$m" .bsp)
  name=${name#bspview-}
  # shellcheck disable=SC2086
  if ! nice -n "${NICE:-10}" "$bin" -quiet --json -threads "${THREADS:-1}" ${OPTS:-} \
      -o "$out/$name.vdg" "$m" > "$out/$name.json" 2> "$out/$name.err"; then
    echo "# $name: compile failed: $(tail -n1 "$out/$name.err")"
    continue
  fi
  if [ ! -s "$out/$name.vdg" ]; then echo "# $name: no graph"; continue; fi
  python3 - "$name" "$out/$name.json" "$out/$name.vdg" <<'PY'
import json, os, sys
name, j, v = sys.argv[1:4]
d = json.load(open(j))
s = d["seconds"]
size = os.path.getsize(v)
faces = d["vdg_faces"]
print("\t".join(str(x) for x in [name, d["vertices"], faces, size, f"{size / max(faces, 1):.1f}",
      f"{s['total']:.2f}", f"{s['reduce']:.2f}", f"{s['guard']:.2f}", f"{s['wall_raise']:.2f}"]))
PY
done
