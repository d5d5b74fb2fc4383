#!/usr/bin/env bash
# Proves the interactive viewer runs without a GPU: starts a virtual X server
# (Xvfb), runs `vdgview view` on a generated map and its graph, grabs the
# screen with xwd and writes a PNG. Installs what it needs (fresh CI machines).
#
# usage: scripts/vdgview-screenshot.sh [MAP.bsp] [OUT.png] [VIEW COMMANDS]
#   defaults: testdata/maps/complex.bsp, target/vdgview-screenshot.png,
#             a view into the map's largest room in clearance mode.
# Prints the viewer's median frame time (software rendering, 960x600).
set -euo pipefail
cd "$(dirname "$0")/.."

MAP=${1:-testdata/maps/complex.bsp}
OUT=${2:-target/vdgview-screenshot.png}
EXEC=${3:-"noclip 1; gopos 1150 1150 300; setang 225 -25; mode 1; mark 850 850 80"}
DISPLAY_NUM=${VDGVIEW_DISPLAY:-:97}
SIZE=960x600

need() { command -v "$1" >/dev/null 2>&1; }
if ! need Xvfb || ! need xwd || [ ! -x /usr/bin/convert ]; then
    echo "installing xvfb, x11-apps (xwd), imagemagick ..." >&2
    SUDO=""; [ "$(id -u)" = 0 ] || SUDO=sudo
    $SUDO apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq xvfb x11-apps imagemagick >/dev/null
fi

cargo build --release -q -p bsp2vdg -p vdgview
WORK=$(mktemp -d)
XVFB_PID=""
VIEW_PID=""
cleanup() {
    [ -n "$VIEW_PID" ] && kill "$VIEW_PID" 2>/dev/null || true
    [ -n "$XVFB_PID" ] && kill "$XVFB_PID" 2>/dev/null || true
    rm -rf "$WORK"
}
trap cleanup EXIT

GRAPH="$WORK/$(basename "${MAP%.bsp}").vdg"
./target/release/bsp2vdg -rl 1.0 -quiet -savesamples -o "$GRAPH" "$MAP"

Xvfb "$DISPLAY_NUM" -screen 0 1024x768x24 -nolisten tcp >"$WORK/xvfb.log" 2>&1 &
XVFB_PID=$!
for _ in $(seq 50); do
    DISPLAY=$DISPLAY_NUM xdpyinfo >/dev/null 2>&1 && break
    sleep 0.1
done
DISPLAY=$DISPLAY_NUM xdpyinfo >/dev/null 2>&1 || { echo "Xvfb did not start" >&2; cat "$WORK/xvfb.log" >&2; exit 1; }

# The viewer runs 60 frames (several seconds of software rendering), long
# enough for the grab below; it prints its median frame time when it closes.
DISPLAY=$DISPLAY_NUM ./target/release/vdgview view "$MAP" "$GRAPH" \
    --samples "${GRAPH%.vdg}.samples.txt" --size $SIZE --exec "$EXEC; stats" --frames 60 \
    >"$WORK/view.log" 2>&1 &
VIEW_PID=$!
sleep 4
kill -0 "$VIEW_PID" 2>/dev/null || { echo "the viewer exited early:" >&2; cat "$WORK/view.log" >&2; exit 1; }
mkdir -p "$(dirname "$OUT")"
# Grab the viewer's window (Xvfb runs no window manager, so it sits wherever X put it).
DISPLAY=$DISPLAY_NUM xwd -name vdgview -silent >"$WORK/screen.xwd"
/usr/bin/convert "$WORK/screen.xwd" "$OUT"
wait "$VIEW_PID"
VIEW_PID=""
cat "$WORK/view.log"
echo "wrote $OUT"
