#!/usr/bin/env bash
# The whole corpus as a test you can run: compiles every map below a folder in batch
# mode (one batch per folder, so maps of the same name in different folders do not
# meet), checks each compiled graph against its map's BSP (`vdgview check` on a small
# sample: leak and visible false positives must be 0), and prints one line per map,
# then per failure kind how many maps and which, then the totals.
#
#   scripts/corpus.sh DIR [BSP2VDG_OPTION...]     # e.g. scripts/corpus.sh ../shared/testmaps
#
# BIN (default target/release) holds bsp2vdg and vdgview; OUT (default
# target/corpus) receives the graphs, logs and reports, mirroring DIR's folders;
# SAMPLES (default 20000) is the check's sample count; NICE (default 5) the
# priority. Maps are compiled with -force (nothing is skipped as up to date).
# Exit 0 when every map compiled and checked clean, 1 otherwise, 2 on bad usage.
set -euo pipefail
[ $# -ge 1 ] || { sed -n 2,16p "$0" >&2; exit 2; }
DIR=$1
shift
[ -d "$DIR" ] || { echo "$DIR is not a folder" >&2; exit 2; }
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BIN=$(cd "${BIN:-$ROOT/target/release}" && pwd)
for b in bsp2vdg vdgview; do
    [ -x "$BIN/$b" ] || { echo "$BIN/$b: no such executable (cargo build --release)" >&2; exit 2; }
done
OUT=${OUT:-$ROOT/target/corpus}
SAMPLES=${SAMPLES:-20000}
NICE=${NICE:-5}
DIR=$(cd "$DIR" && pwd)
mkdir -p "$OUT"
REPORT="$OUT/report.jsonl"
: >"$REPORT"

mapfile -t folders < <(find "$DIR" -name '*.bsp' -printf '%h\n' | sort -u)
[ ${#folders[@]} -gt 0 ] || { echo "no .bsp below $DIR" >&2; exit 2; }
for folder in "${folders[@]}"; do
    rel=${folder#"$DIR"}
    rel=${rel#/}
    out="$OUT/${rel:-.}"
    mkdir -p "$out"
    mapfile -t maps < <(find "$folder" -maxdepth 1 -name '*.bsp' | sort)
    echo "== ${rel:-.}: ${#maps[@]} maps" >&2
    # Batch mode wants two maps or more; a single map gets -o FILE.
    if [ ${#maps[@]} -eq 1 ]; then
        dest=(-o "$out/$(basename "${maps[0]%.bsp}").vdg")
    else
        dest=(-o "$out")
    fi
    set +e
    nice -n "$NICE" "$BIN/bsp2vdg" "${maps[@]}" "${dest[@]}" -force -quiet -json "$@" \
        >"$out/batch.json" 2>"$out/batch.err"
    set -e
    python3 - "$out/batch.json" "$out" "$REPORT" "${maps[@]}" <<'EOF'
import json, sys, os
path, out, report, maps = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
try:
    doc = json.load(open(path))
    objs = doc["maps"] if "maps" in doc else [doc]
except Exception as e:
    err = open(os.path.join(out, "batch.err")).read().strip().splitlines()
    why = err[-1] if err else f"no report ({e})"
    objs = [{"map": m, "ok": False, "error": why} for m in maps]
with open(report, "a") as r:
    for o in objs:
        o["vdg"] = os.path.join(out, os.path.basename(o["map"])[:-4] + ".vdg")
        r.write(json.dumps(o) + "\n")
EOF
done

# Check every compiled graph against its map.
CHECKED="$OUT/checked.jsonl"
: >"$CHECKED"
while IFS= read -r line; do
    ok=$(python3 -c 'import json,sys; print(json.loads(sys.argv[1])["ok"])' "$line")
    map=$(python3 -c 'import json,sys; print(json.loads(sys.argv[1])["map"])' "$line")
    vdg=$(python3 -c 'import json,sys; print(json.loads(sys.argv[1])["vdg"])' "$line")
    check='null'
    if [ "$ok" = True ] && [ -f "$vdg" ]; then
        check=$(nice -n "$NICE" "$BIN/vdgview" check --samples "$SAMPLES" --json "$map" "$vdg" 2>"$OUT/check.err" || true)
        [ -n "$check" ] || check="{\"error\": $(python3 -c 'import json,sys; print(json.dumps(open(sys.argv[1]).read().strip()))' "$OUT/check.err")}"
    fi
    python3 -c 'import json,sys; o=json.loads(sys.argv[1]); o["check"]=json.loads(sys.argv[2]); print(json.dumps(o))' "$line" "$check" >>"$CHECKED"
done <"$REPORT"

python3 - "$CHECKED" "$DIR" <<'EOF'
import json, re, sys
from collections import defaultdict
rows = [json.loads(l) for l in open(sys.argv[1])]
root = sys.argv[2].rstrip("/") + "/"
def name(m):
    return m[len(root):] if m.startswith(root) else m
def kind(error, m):
    # The reason without the map's path and with numbers as N: one kind per cause.
    e = error.replace(m + ": ", "").replace(m, "MAP")
    e = re.sub(r"-?\d+(\.\d+)?", "N", e)
    return e
kinds = defaultdict(list)
leaks = fps = cam_fps = checked = unclean = 0
print(f"{'map':<52} {'status':<9} {'game':<8} {'unusable':>8} {'vertices':>8} {'leak':>6} {'fp':>6} {'cam fp':>6} {'time':>8}")
for r in rows:
    m = name(r["map"])
    if not r["ok"]:
        kinds[kind(r.get("error", "?"), r["map"])].append(m)
        print(f"{m:<52} {'FAILED':<9} {r.get('error','')[:120]}")
        continue
    c = r.get("check") or {}
    game = (r.get("game") or "")[:8]
    t = r.get("seconds", {}).get("total", 0.0)
    if "leaked" in c:
        checked += 1
        lk, fp, cfp = c["leaked"], c["false_positives"], c.get("camera_false_positives", 0)
        leaks += lk; fps += fp; cam_fps += cfp
        clean = lk == 0 and fp == 0 and cfp == 0
        unclean += not clean
        status = "ok" if clean else "UNCLEAN"
        leak_note = " (map leaks)" if r.get("leak") else ""
        print(f"{m:<52} {status:<9} {game:<8} {r.get('unusable_faces',0):>8} {r.get('vertices') or 0:>8} {lk:>6} {fp:>6} {cfp:>6} {t:>7.1f}s{leak_note}")
    else:
        unclean += 1
        print(f"{m:<52} {'UNCHECKED':<9} {c.get('error','no check')[:120]}")
print()
print("failures by kind:")
if not kinds:
    print("  none")
for k, ms in sorted(kinds.items(), key=lambda kv: -len(kv[1])):
    print(f"  {len(ms):>4}  {k}")
    for m in ms:
        print(f"        {m}")
failed = sum(len(v) for v in kinds.values())
print()
print(f"{len(rows)} maps: {len(rows) - failed} compiled, {failed} failed; {checked} checked: "
      f"leak {leaks}, visible fp {fps}, camera fp {cam_fps}, {unclean} not clean")
sys.exit(0 if failed == 0 and unclean == 0 else 1)
EOF
