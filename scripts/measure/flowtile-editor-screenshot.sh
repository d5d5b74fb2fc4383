#!/usr/bin/env bash
# Screenshots of the flow tile editor (`flowtile-bake edit`), taken twice
# and compared byte for byte.
#
# 1. Headless (always): a scripted session on the river spec
#    (testdata/flowtiles/editor-demo.txt) rendered by the editor's own
#    CPU rasteriser of egui's output — no display, no GPU, nothing to install
#    beyond Rust. The picture must be non-empty and the same bytes twice
#    (fixed seed, fixed particle time).
# 2. The window (WINDOW=1, or when Xvfb is already there): the same session
#    in the real eframe window under a virtual X server (Xvfb, Mesa's
#    software OpenGL); xdotool clicks a slot and presses F (fill); grabbed
#    with xwd. Installs xvfb, x11-apps, x11-utils,
#    xdotool, libgl1-mesa-dri and imagemagick from Debian when missing.
#
# usage: scripts/flowtile-editor-screenshot.sh [OUT.png]
#   default OUT: target/flowtile-editor.png (de_dust2: OUT-de_dust2.png, the
#   window's: OUT-window.png)
set -euo pipefail
cd "$(dirname "$(readlink -f "$0")")/../.."
OUT=${1:-target/flowtile-editor.png}
SPEC=testdata/flowtiles/river.toml
SCRIPT=testdata/flowtiles/editor-demo.txt
SIZE=${SIZE:-1280x800}

# FLOWTILE_BAKE=PATH uses that binary instead of building the release one.
if [ -n "${FLOWTILE_BAKE:-}" ]; then
    BIN=$FLOWTILE_BAKE
else
    cargo build --release -q -p flowtile-bake
    BIN=target/release/flowtile-bake
fi
WORK=$(mktemp -d)
XVFB_PID=""
APP_PID=""
cleanup() {
    [ -n "$APP_PID" ] && kill "$APP_PID" 2>/dev/null || true
    [ -n "$XVFB_PID" ] && kill "$XVFB_PID" 2>/dev/null || true
    rm -rf "$WORK"
}
trap cleanup EXIT

mkdir -p "$(dirname "$OUT")"
# The script saves and bakes into the working directory: run it there.
ABS_BIN=$(cd "$(dirname "$BIN")" && pwd)/$(basename "$BIN")
for run in 1 2; do
    (cd "$WORK" && "$ABS_BIN" edit "$OLDPWD/$SPEC" --script "$OLDPWD/$SCRIPT" \
        --screenshot "shot$run.png" --size "$SIZE" >"log$run.txt")
done
size=$(stat -c %s "$WORK/shot1.png")
if [ "$size" -lt 20000 ]; then
    echo "screenshot is suspiciously small ($size bytes)" >&2
    exit 1
fi
if ! cmp -s "$WORK/shot1.png" "$WORK/shot2.png"; then
    echo "the two headless screenshots differ" >&2
    exit 1
fi
cp "$WORK/shot1.png" "$OUT"
tail -n 3 "$WORK/log1.txt"
echo "wrote $OUT ($size bytes; identical in two runs)"

# With the shared maps: the region of de_dust2 over the map's top view.
MAP=../shared/testmaps/goldsrc/nonfree/bspview-cstrike-de_dust2.bsp
if [ -f "$MAP" ]; then
    "$BIN" region "$MAP" --tile 96 -o "$WORK/dust2.toml" >/dev/null
    DOUT="${OUT%.png}-de_dust2.png"
    for run in 1 2; do
        "$BIN" edit "$WORK/dust2.toml" --script testdata/flowtiles/editor-dust2.txt \
            --screenshot "$WORK/shotd$run.png" --size "$SIZE" >/dev/null
    done
    cmp -s "$WORK/shotd1.png" "$WORK/shotd2.png" || { echo "the two de_dust2 screenshots differ" >&2; exit 1; }
    cp "$WORK/shotd1.png" "$DOUT"
    echo "wrote $DOUT (identical in two runs)"
else
    echo "skip de_dust2: $MAP not found"
fi

if [ "${WINDOW:-0}" != 1 ] && ! command -v Xvfb >/dev/null 2>&1; then
    echo "skipping the window under Xvfb (WINDOW=1 installs and runs it)"
    exit 0
fi
need() { command -v "$1" >/dev/null 2>&1; }
if ! need Xvfb || ! need xwd || ! need xdpyinfo || ! need xdotool || [ ! -x /usr/bin/convert ] ||
    ! ls /usr/lib/*/dri/swrast_dri.so >/dev/null 2>&1; then
    echo "installing xvfb, x11-apps (xwd), x11-utils (xdpyinfo), xdotool, libgl1-mesa-dri, imagemagick ..." >&2
    SUDO=""; [ "$(id -u)" = 0 ] || SUDO=sudo
    $SUDO apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq xvfb x11-apps x11-utils xdotool \
        libgl1-mesa-dri imagemagick >/dev/null
fi
DISPLAY_NUM=${EDITOR_DISPLAY:-:96}
Xvfb "$DISPLAY_NUM" -screen 0 1600x1000x24 -nolisten tcp >"$WORK/xvfb.log" 2>&1 &
XVFB_PID=$!
for _ in $(seq 50); do
    DISPLAY=$DISPLAY_NUM xdpyinfo >/dev/null 2>&1 && break
    sleep 0.1
done
DISPLAY=$DISPLAY_NUM xdpyinfo >/dev/null 2>&1 || { echo "Xvfb did not start" >&2; cat "$WORK/xvfb.log" >&2; exit 1; }
(cd "$WORK" && DISPLAY=$DISPLAY_NUM LIBGL_ALWAYS_SOFTWARE=1 "$ABS_BIN" edit "$OLDPWD/$SPEC" \
    --script "$OLDPWD/$SCRIPT" --window --seconds 12 --size "$SIZE" >"window.log" 2>&1) &
APP_PID=$!
sleep 8
kill -0 "$APP_PID" 2>/dev/null || { echo "the editor's window closed early:" >&2; cat "$WORK/window.log" >&2; exit 1; }
# A person's input through XTEST: click slot (8, 3) with the Tiles tool (its
# palette opens), then F fills the 15 empty slots (the status bar says so).
export DISPLAY=$DISPLAY_NUM
WID=$(xdotool search --sync --name '^flowtile-bake edit$' | tail -1)
xdotool windowfocus --sync "$WID" || echo "warning: could not focus the editor" >&2
xdotool mousemove 452 413 click 1 && sleep 1 &&
    xdotool keydown f && sleep 0.3 && xdotool keyup f && sleep 1.5 ||
    echo "warning: xdotool could not click or press F" >&2
WOUT="${OUT%.png}-window.png"
DISPLAY=$DISPLAY_NUM xwd -root -silent >"$WORK/screen.xwd"
/usr/bin/convert "$WORK/screen.xwd" -crop "${SIZE}+0+0" +repage "$WOUT"
wait "$APP_PID" || true
APP_PID=""
echo "wrote $WOUT (the window under Xvfb; particles move in real time, so this one is not compared)"
