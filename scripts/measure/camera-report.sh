#!/usr/bin/env bash
# The camera measured on every GoldSrc map in ../shared/testmaps (goldsrc/, goldsrc/nonfree/
# and the Counter-Strike maps of goldsrc/nonfree/cs/): compiles each map's graph, replays the
# spawn routes, the nav-mesh routes where a .nav sits beside the map, and the playtests of
# testmaps/demos/ recorded on the map (GoldSrc .dem), at each frame time with every camera,
# and writes
#   OUT/report.md              Markdown table: one row per map, route source, dt and camera
#   OUT/summary.md             Markdown table: all maps together per dt and camera (frames weighted)
#   OUT/targets.md             the VDG camera per map against the targets (seen >= 97 %, 0 solid,
#                              0 near-plane, 0 jumps, <= 1 cut/min), with the figures that say
#                              why a map misses (target outside, false occlusions, longest occlusion)
#   OUT/outside.md             where the target stood outside Volume(VDG), per map
#   OUT/json/MAP-SRC-dtN.json  the replay --json reports
#   OUT/plots/MAP-SRC-dtN/     speed, occlusion and summary charts per replay
#   OUT/summary-dtN.png        the measures per camera across all maps
# Progress goes to the terminal.
#   scripts/camera-report.sh [-dt "1/60 1/30"] [-camera LIST] [-params cam.toml] [-routes N] [-seed N] [-compile "OPTIONS"] [-out DIR]
# -compile: bsp2vdg options for the graphs (e.g. "-sd 12 -md 4"), to compare graphs made with
# other options on the same routes; OUT/graphs is compiled again when they change.
# -params: camera parameters for the VDG camera (TOML, as `vdgview replay --params`), to
# compare parameter sets on the same graphs (OUT/graphs is reused when it holds them).
# -seed: the seed of the route choices (`vdgview replay --seed`, default 1): other routes on the
# same maps, to check that a decision holds beyond the routes it was measured on.
#   MAPS="a.bsp b.bsp" scripts/camera-report.sh      (only these maps)
#   SHARED=/path/to/shared                            (default ../shared)
#   BSP2VDG=/path/to/bsp2vdg                          (compile with another build, e.g. to
#                                                      compare two commits' graphs)
#   VDGVIEW=/path/to/vdgview                          (replay with another build)
#   NOBUILD=1                                         (use the binaries as they are)
set -euo pipefail
cd "$(dirname "$(readlink -f "$0")")/../.."
dts="1/60 1/30"
cameras=""
params=""
compile_opts=""
max_routes=8
seed=1
out=target/camera-report
while [ $# -gt 0 ]; do
  case "$1" in
    -dt) dts=$2; shift 2 ;;
    -camera) cameras=$2; shift 2 ;;
    -params) params=$2; shift 2 ;;
    -routes) max_routes=$2; shift 2 ;;
    -seed) seed=$2; shift 2 ;;
    -compile) compile_opts=$2; shift 2 ;;
    -out) out=$2; shift 2 ;;
    *) echo "usage: $0 [-dt \"1/60 1/30\"] [-camera LIST] [-params cam.toml] [-routes N] [-seed N] [-compile \"OPTIONS\"] [-out DIR]" >&2; exit 2 ;;
  esac
done
shared=${SHARED:-../shared}
compiler=${BSP2VDG:-./target/release/bsp2vdg}
viewer=${VDGVIEW:-./target/release/vdgview}
if [ -z "${NOBUILD:-}" ]; then
  echo "camera-report: building (release) ..." >&2
  cargo build --release -q -p bsp2vdg -p vdgview
fi
shopt -s nullglob
if [ -n "${MAPS:-}" ]; then
  # shellcheck disable=SC2206
  maps=($MAPS)
else
  maps=("$shared"/testmaps/goldsrc/*.bsp "$shared"/testmaps/goldsrc/nonfree/*.bsp "$shared"/testmaps/goldsrc/nonfree/cs/*.bsp)
fi
# Demos and the map each was recorded on (matched to a map file by its name's end).
declare -A demo_map=()
for d in "$shared"/testmaps/demos/*.dem; do
  mapname=$("$viewer" demo --json "$d" 2>/dev/null | python3 -c 'import json,sys; print(json.load(sys.stdin)["map"])' 2>/dev/null) || continue
  [ -n "$mapname" ] && demo_map[$d]=$mapname
done
if [ ${#maps[@]} -eq 0 ]; then
  echo "camera-report: no GoldSrc maps under $shared/testmaps/goldsrc (set SHARED or MAPS)" >&2
  exit 1
fi
mkdir -p "$out/graphs" "$out/json" "$out/plots" "$out/logs"
# Graphs made with other compile options are not reused.
if [ "$(cat "$out/graphs/.options" 2>/dev/null)" != "$compile_opts" ]; then
  rm -f "$out/graphs/"*.vdg
  printf '%s' "$compile_opts" > "$out/graphs/.options"
fi
camera_opt=()
[ -n "$cameras" ] && camera_opt=(--camera "$cameras")
[ -n "$params" ] && camera_opt+=(--params "$params")
i=0
for m in "${maps[@]}"; do
  i=$((i + 1))
  name=$(basename "$m" .bsp)
  vdg="$out/graphs/$name.vdg"
  if [ ! -s "$vdg" ] || [ "$m" -nt "$vdg" ]; then
    printf '[%d/%d] %s: compiling graph ...\n' "$i" "${#maps[@]}" "$name" >&2
    # shellcheck disable=SC2086 # the options are words
    if ! "$compiler" -quiet $compile_opts -o "$vdg" "$m" 2> "$out/logs/$name.compile.err"; then
      printf '[%d/%d] %s: compile failed: %s\n' "$i" "${#maps[@]}" "$name" "$(tail -n1 "$out/logs/$name.compile.err")" >&2
      continue
    fi
  fi
  sources=(spawns)
  nav="${m%.bsp}.nav"
  [ -f "$nav" ] && sources+=("nav:$nav")
  for d in "${!demo_map[@]}"; do
    mn=${demo_map[$d]}
    case "$name" in "$mn" | *[-_.]"$mn") sources+=("demo:$d") ;; esac
  done
  for src in "${sources[@]}"; do
    tag=${src%%:*}
    for dt in $dts; do
      dtn=${dt#1/}
      key="$name-$tag-dt$dtn"
      printf '[%d/%d] %s: %s routes, dt %s ...\n' "$i" "${#maps[@]}" "$name" "$tag" "$dt" >&2
      if ! nice -n 10 "$viewer" replay "$m" "$vdg" --routes "$src" --dt "$dt" \
          --max-routes "$max_routes" --seed "$seed" "${camera_opt[@]}" --json --plots "$out/plots/$key" \
          > "$out/json/$key.json.part" 2> "$out/logs/$key.err"; then
        printf '[%d/%d] %s: replay failed: %s\n' "$i" "${#maps[@]}" "$name" "$(tail -n1 "$out/logs/$key.err")" >&2
        rm -f "$out/json/$key.json.part"
      else
        mv "$out/json/$key.json.part" "$out/json/$key.json"
      fi
    done
  done
done
for dt in $dts; do
  dtn=${dt#1/}
  reports=("$out"/json/*-dt"$dtn".json)
  [ ${#reports[@]} -gt 0 ] && "$viewer" replay-summary -o "$out/summary-dt$dtn.png" \
    --title "camera measures per map and route source, dt $dt s" "${reports[@]}"
done
python3 - "$out" <<'PY'
import json, glob, os, sys
out = sys.argv[1]
rows, outside = [], []
for p in sorted(glob.glob(os.path.join(out, "json", "*.json"))):
    r = json.load(open(p))
    key = os.path.basename(p)[:-5]
    mapname, rest = key.rsplit("-", 2)[0], key.rsplit("-", 2)[1:]
    src, dt = rest[0], "1/" + rest[1][2:]
    routes = r["routes"]
    outside.append((mapname, src, dt, r["target_outside_fraction"], r["target_outside"], routes))
    for cam, c in r["cameras"].items():
        rows.append((mapname, src, dt, cam, routes["count"], c))
def pct(x): return f"{100*x:.2f}"
with open(os.path.join(out, "report.md"), "w") as f:
    f.write("| map | routes | dt | camera | frames | solid | near-plane | visible % | hull visible % | longest occlusion s | jumps | stalls | RMS jerk | mean abs(d-d_μ) | cuts/min | median µs | target outside % | false occlusion % |\n")
    f.write("|---|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n")
    for m, s, dt, cam, n, c in rows:
        f.write(f"| {m} | {s} ({n}) | {dt} | {cam} | {c['frames']} | {c['solid_frames']} | {c['nearplane_frames']} | {pct(c['visible_fraction'])} | {pct(c['hull_visible_mean'])} | {c['longest_occlusion_s']:.2f} | {c['jumps']} | {c['stalls']} | {c['rms_jerk']:.0f} | {c['mean_abs_dist_error']:.1f} | {c['cuts_per_min']:.2f} | {c['median_us']:.1f} | {pct(c['target_outside_fraction'])} | {pct(c.get('graph_false_occlusion', 0.0))} |\n")
# All maps together, frames weighted: the acceptance figures.
agg = {}
for m, s, dt, cam, n, c in rows:
    a = agg.setdefault((dt, cam), dict(frames=0, seconds=0.0, solid=0, near=0, vis=0.0, vis_in=0.0, inside=0.0, jumps=0, cuts=0, jerk2=0.0, seen=0.0, false_occl=0.0,
                                       hull=0.0, longest=0.0, stalls=0, dist=0.0, median_us=0.0, reports=0))
    fr = c["frames"]
    a["frames"] += fr; a["seconds"] += c["seconds"]; a["solid"] += c["solid_frames"]; a["near"] += c["nearplane_frames"]
    a["vis"] += c["visible_fraction"] * fr; a["jumps"] += c["jumps"]; a["cuts"] += c["cuts"]
    a["hull"] += c["hull_visible_mean"] * fr; a["longest"] = max(a["longest"], c["longest_occlusion_s"])
    a["stalls"] += c["stalls"]; a["dist"] += c["mean_abs_dist_error"] * fr
    a["median_us"] += c["median_us"]; a["reports"] += 1
    a["jerk2"] += c["rms_jerk"] ** 2 * fr
    inside = (1 - c["target_outside_fraction"]) * fr
    a["inside"] += inside; a["vis_in"] += c.get("visible_fraction_target_inside", 0.0) * inside
    # False occlusions are a share of the frames the BSP sees the target in.
    seen = c["visible_fraction"] * fr
    a["seen"] += seen; a["false_occl"] += c.get("graph_false_occlusion", 0.0) * seen
def jerk(a): return (a["jerk2"] / max(a["frames"], 1)) ** 0.5
with open(os.path.join(out, "summary.md"), "w") as f:
    # The README's camera table is this file as it stands.
    f.write("| dt | camera | frames | solid | near-plane | visible % | visible % (target inside the volume) | hull visible % | longest occlusion s | jumps | stalls | RMS jerk u/s³ | jerk / chase | jerk / spring arm | mean abs(d−d_μ) | cuts/min | mean of median µs | target outside % | false occlusion % |\n")
    f.write("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n")
    for (dt, cam), a in sorted(agg.items()):
        n = max(a["frames"], 1)
        ref = lambda other: f"{100 * jerk(a) / jerk(agg[(dt, other)]):.1f} %" if (dt, other) in agg and jerk(agg[(dt, other)]) > 0 else "-"
        f.write(f"| {dt} | {cam} | {a['frames']} | {a['solid']} | {a['near']} | {pct(a['vis'] / n)} | {pct(a['vis_in'] / max(a['inside'], 1))} | {pct(a['hull'] / n)} | {a['longest']:.2f} | {a['jumps']} | {a['stalls']} | {jerk(a):.0f} | {ref('chase')} | {ref('springarm')} | {a['dist'] / n:.1f} | {a['cuts'] / max(a['seconds'] / 60, 1e-9):.2f} | {a['median_us'] / max(a['reports'], 1):.1f} | {pct(1 - a['inside'] / n)} | {pct(a['false_occl'] / max(a['seen'], 1))} |\n")
# The VDG camera per map and route set against the targets: seen >= 97 %, 0 solid, 0 near-plane,
# 0 jumps, <= 1 cut a minute, RMS jerk <= 10 % of the chase cam's; with the figures that say why a
# map misses (target outside the volume, false occlusions, longest occlusion).
chase = {(m, s, dt): c for m, s, dt, cam, n, c in rows if cam == "chase"}
with open(os.path.join(out, "targets.md"), "w") as f:
    f.write("| map | routes | dt | frames | seen % | solid | near-plane | jumps | cuts/min | jerk / chase | longest occlusion s | target outside % | false occlusion % | misses |\n")
    f.write("|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n")
    missed = 0
    for m, s, dt, cam, n, c in rows:
        if cam != "vdg":
            continue
        ch = chase.get((m, s, dt))
        jr = c["rms_jerk"] / ch["rms_jerk"] if ch and ch["rms_jerk"] > 0 else float("nan")
        miss = []
        if c["visible_fraction"] < 0.97: miss.append("seen")
        if c["solid_frames"]: miss.append("solid")
        if c["nearplane_frames"]: miss.append("near-plane")
        if c["jumps"]: miss.append("jumps")
        if c["cuts_per_min"] > 1.0: miss.append("cuts")
        if jr == jr and jr > 0.10: miss.append("jerk")
        missed += bool(miss)
        f.write(f"| {m} | {s} ({n}) | {dt} | {c['frames']} | {pct(c['visible_fraction'])} | {c['solid_frames']} | {c['nearplane_frames']} | {c['jumps']} | {c['cuts_per_min']:.2f} | {100 * jr:.1f} % | {c['longest_occlusion_s']:.2f} | {pct(c['target_outside_fraction'])} | {pct(c.get('graph_false_occlusion', 0.0))} | {', '.join(miss) or '-'} |\n")
    f.write(f"\n{missed} route sets miss a target.\n")
with open(os.path.join(out, "outside.md"), "w") as f:
    f.write("# Target positions outside Volume(VDG)\n\n")
    for m, s, dt, frac, runs, routes in outside:
        if dt != "1/60":
            continue
        f.write(f"## {m} ({s}): {pct(frac)} % of {routes['frames']} frames, {len(runs)} runs\n\n")
        for o in runs[:200]:
            x, y, z = o["origin"]
            f.write(f"- {o['route']} t {o['t0']:.2f}-{o['t1']:.2f} s at ({x:.0f}, {y:.0f}, {z:.0f})\n")
        f.write("\n")
print(f"camera-report: wrote {out}/summary.md, {out}/report.md, {out}/targets.md, {out}/outside.md and the plots", file=sys.stderr)
PY
cat "$out/summary.md"
