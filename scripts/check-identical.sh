#!/usr/bin/env bash
# Proves that two builds behave the same: every output the product writes for the
# shared maps and the repository's own test data is compared byte for byte.
#
#   scripts/check-identical.sh OLD_BIN_DIR NEW_BIN_DIR
#
# Each BIN_DIR holds the release binaries bsp2vdg, vdgview and flowtile-bake (e.g. a
# worktree's target/release). Compared, per map (../shared/testmaps, every .bsp below
# it, and testdata/maps): the .vdg at the default options; the camera replay CSVs
# (spawn routes, and nav routes where a .nav sits beside the map) with the per-frame
# compute time removed (it is a wall-clock measurement, never identical); and the
# flow tile files baked from testdata/flowtiles and from a region of two maps.
#
# Prints one line per output that differs and a closing "N identical, N differ"
# line; exits 1 when anything differs or an old/new run failed differently.
# SHARED overrides ../shared, OUT the scratch folder (default target/check-identical),
# MAPS a space-separated list of maps instead of every shared one.
set -euo pipefail
cd "$(dirname "$0")/.."
[ $# -eq 2 ] || { echo "usage: $0 OLD_BIN_DIR NEW_BIN_DIR" >&2; exit 2; }
OLD=$(cd "$1" && pwd)
NEW=$(cd "$2" && pwd)
for b in bsp2vdg vdgview flowtile-bake; do
    for d in "$OLD" "$NEW"; do
        [ -x "$d/$b" ] || { echo "$d/$b: no such executable" >&2; exit 2; }
    done
done
SHARED=${SHARED:-../shared}
OUT=${OUT:-target/check-identical}
rm -rf "$OUT"
mkdir -p "$OUT/old" "$OUT/new"

if [ -n "${MAPS:-}" ]; then
    read -r -a maps <<<"$MAPS"
else
    mapfile -t maps < <( { find "$SHARED/testmaps" -name '*.bsp' 2>/dev/null; ls testdata/maps/*.bsp; } | sort)
fi
[ -d "$SHARED/testmaps" ] || echo "note: $SHARED/testmaps is absent; only testdata/maps is compared"

same=0
differ=0
# same_but_build OLD NEW — two graphs that differ only in the build identity every
# .vdg records (`tool.build=…` in its metadata, and so the checksum over it): what
# two builds of the same compiler code path are expected to write.
same_but_build() {
    case "$1" in *.vdg) ;; *) return 1 ;; esac
    python3 - "$1" "$2" <<'PY'
import re, sys
def masked(path):
    data = bytearray(open(path, "rb").read())
    if len(data) >= 16:
        data[8:16] = bytes(8)  # XXH64 checksum of everything after it
    return re.sub(rb"tool\.build=[0-9a-f]{16}\n", b"tool.build=\n", bytes(data))
sys.exit(0 if masked(sys.argv[1]) == masked(sys.argv[2]) else 1)
PY
}
# compare LABEL OLD_FILE NEW_FILE
compare() {
    if [ ! -e "$2" ] && [ ! -e "$3" ]; then
        return
    fi
    if cmp -s "$2" "$3" || same_but_build "$2" "$3"; then
        same=$((same + 1))
    else
        differ=$((differ + 1))
        echo "DIFFERS: $1"
    fi
}
# run SIDE LABEL CMD... — runs one side's command, keeping its exit status and error
# line so that a failure on both sides compares as identical failure text.
run() {
    local side=$1 label=$2
    shift 2
    local status=0
    "$@" >"$OUT/$side/$label.stdout" 2>"$OUT/$side/$label.stderr" || status=$?
    echo "$status" >"$OUT/$side/$label.status"
}

i=0
for m in "${maps[@]}"; do
    i=$((i + 1))
    name=$(basename "$m" .bsp)
    printf '[%d/%d] %s\n' "$i" "${#maps[@]}" "$name" >&2
    for side in old new; do
        bin=$OLD
        [ $side = new ] && bin=$NEW
        run $side "$name-compile" "$bin/bsp2vdg" -quiet -nolog -o "$OUT/$side/$name.vdg" "$m"
        # The .err file's text is part of the behaviour too (a refused map); its first
        # line repeats the command line, whose output path names the side, after the
        # tool's name and build identity, which differs between any two builds.
        if [ -e "$OUT/$side/$name.err" ]; then
            sed -e "s#$OUT/$side/#OUT/#g" -e 's/(build [0-9a-f]\{16\})/(build)/' \
                "$OUT/$side/$name.err" >"$OUT/$side/$name-compile.err"
            rm "$OUT/$side/$name.err"
        fi
        if [ -e "$OUT/$side/$name.vdg" ]; then
            routes=(spawns)
            nav="${m%.bsp}.nav"
            [ -e "$nav" ] && routes+=("nav:$nav")
            for r in "${routes[@]}"; do
                tag=${r%%:*}
                dir="$OUT/$side/$name-replay-$tag"
                run $side "$name-replay-$tag" "$bin/vdgview" replay "$m" "$OUT/$side/$name.vdg" \
                    --routes "$r" --max-routes 4 --csv "$dir"
                for csv in "$dir"/*.csv; do
                    [ -e "$csv" ] || continue
                    # Drop the column "micros" (compute time per frame).
                    awk -F, -v OFS=, 'NR==1{for(c=1;c<=NF;c++) if($c=="micros") drop=c}
                        {if(drop){$drop=""}; print}' "$csv" >"$csv.cmp"
                done
            done
        fi
    done
    compare "$name.vdg" "$OUT/old/$name.vdg" "$OUT/new/$name.vdg"
    compare "$name compile status" "$OUT/old/$name-compile.status" "$OUT/new/$name-compile.status"
    compare "$name compile .err" "$OUT/old/$name-compile.err" "$OUT/new/$name-compile.err"
    for d in "$OUT/old/$name"-replay-*/; do
        [ -d "$d" ] || continue
        tag=$(basename "$d")
        for csv in "$d"*.csv.cmp; do
            [ -e "$csv" ] || continue
            compare "$tag/$(basename "$csv" .cmp)" "$csv" "$OUT/new/$tag/$(basename "$csv")"
        done
        compare "$tag status" "$OUT/old/$tag.status" "$OUT/new/$tag.status"
    done
done

# Flow tiles: every spec the repository ships, and a region of a shipped map.
for spec in testdata/flowtiles/*.toml; do
    name=$(basename "$spec" .toml)
    for side in old new; do
        bin=$OLD
        [ $side = new ] && bin=$NEW
        run $side "ftb-$name" "$bin/flowtile-bake" tile "$spec" -o "$OUT/$side/$name.ftb"
    done
    compare "$name.ftb" "$OUT/old/$name.ftb" "$OUT/new/$name.ftb"
done
for m in testdata/maps/complex.bsp testdata/maps/two_rooms.bsp \
    "$SHARED/testmaps/goldsrc/nonfree/bspview-cstrike-de_dust2.bsp"; do
    [ -e "$m" ] || continue
    name=$(basename "$m" .bsp)
    for side in old new; do
        bin=$OLD
        [ $side = new ] && bin=$NEW
        run $side "region-$name" "$bin/flowtile-bake" region "$m" --tile 64 -o "$OUT/$side/region-$name.toml"
        [ -e "$OUT/$side/region-$name.toml" ] &&
            run $side "region-tile-$name" "$bin/flowtile-bake" tile "$OUT/$side/region-$name.toml" \
                -o "$OUT/$side/region-$name.ftb"
    done
    compare "region-$name.toml" "$OUT/old/region-$name.toml" "$OUT/new/region-$name.toml"
    compare "region-$name.ftb" "$OUT/old/region-$name.ftb" "$OUT/new/region-$name.ftb"
done

echo "check-identical: $same identical, $differ differ"
[ "$differ" -eq 0 ]
