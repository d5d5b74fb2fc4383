#!/usr/bin/env bash
# Proves the interactive viewer runs without a GPU: starts a virtual X server
# (Xvfb), runs `vdgview view` on a generated map and its graph, grabs the
# viewer's window with xwd and writes a PNG. Installs what it needs (fresh CI
# machines): the viewer itself needs only libX11/libXcursor at run time (dlopen),
# no GPU and no OpenGL — it shows vdgview's own software framebuffer.
#
# usage: scripts/vdgview-screenshot.sh [MAP.bsp] [OUT.png] [VIEW COMMANDS]
#   defaults: testdata/maps/complex.bsp, target/vdgview-screenshot.png,
#             a view into a room, wireframe mode, a marked point and its path;
#             then xdotool types a console command (Tab, "clearance", Enter)
#             and presses K, so keyboard input is proven too.
# Prints the viewer's median frame time (software rendering, 960x600).
# VIEW_ARGS adds options to `vdgview view`, e.g. VIEW_ARGS="--follow spawns" plays the
# map's first spawn route with the VDG camera (then EXEC="" keeps the camera's view).
set -euo pipefail
cd "$(dirname "$(readlink -f "$0")")/../.."

MAP=${1:-testdata/maps/complex.bsp}
OUT=${2:-target/vdgview-screenshot.png}
EXEC=${3-"noclip 1; gopos 1150 1150 300; setang 225 -25; mode 1; mark 850 850 80"}
# shellcheck disable=SC2206
VIEW_ARGS=(${VIEW_ARGS:-})
DISPLAY_NUM=${VDGVIEW_DISPLAY:-:97}
SIZE=960x600

need() { command -v "$1" >/dev/null 2>&1; }
if ! need Xvfb || ! need xwd || ! need xdpyinfo || ! need xdotool || [ ! -x /usr/bin/convert ]; then
    echo "installing xvfb, x11-apps (xwd), x11-utils (xdpyinfo), xdotool, imagemagick ..." >&2
    SUDO=""; [ "$(id -u)" = 0 ] || SUDO=sudo
    $SUDO apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq xvfb x11-apps x11-utils xdotool imagemagick >/dev/null
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

# The viewer runs for 15 s, long enough for the keys and the grab below; it
# prints its median frame time when it closes.
DISPLAY=$DISPLAY_NUM ./target/release/vdgview view "$MAP" "$GRAPH" \
    --samples "${GRAPH%.vdg}.samples.txt" --size $SIZE --exec "$EXEC; stats" --seconds 15 \
    ${VIEW_ARGS[@]+"${VIEW_ARGS[@]}"} \
    >"$WORK/view.log" 2>&1 &
VIEW_PID=$!
sleep 2
kill -0 "$VIEW_PID" 2>/dev/null || { echo "the viewer exited early:" >&2; cat "$WORK/view.log" >&2; exit 1; }
# Keyboard: open the console, run `clearance` (reports the crosshair point), close
# it, then K hides the samples. Each key is held across a few frames.
# Keys go through XTEST to the focused window (Xvfb runs no window manager,
# so the script focuses it itself).
export DISPLAY=$DISPLAY_NUM
WID=$(xdotool search --sync --name '^vdgview$' | tail -1)
xdotool windowfocus --sync "$WID" || echo "warning: could not focus the viewer" >&2
for k in Tab c l e a r a n c e Return k; do
    xdotool keydown "$k" && sleep 0.25 && xdotool keyup "$k" && sleep 0.1 ||
        echo "warning: xdotool could not press $k" >&2
done
sleep 1
mkdir -p "$(dirname "$OUT")"
# Grab the viewer's window (Xvfb runs no window manager, so it sits wherever X put it).
xwd -name vdgview -silent >"$WORK/screen.xwd"
/usr/bin/convert "$WORK/screen.xwd" "$OUT"
wait "$VIEW_PID"
VIEW_PID=""
cat "$WORK/view.log"
echo "wrote $OUT"
