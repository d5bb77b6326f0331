#!/usr/bin/env bash
# The 3D view still draws after the window is resized during a scan, as a window manager or a user maximising the
# window does. It stayed grey (the panel colour) until the tab was switched while render() held the OpenGL widget's
# updates around each render. Run under its own X server:
#   xvfb-run -a -s "-screen 0 1600x1000x24" view-after-resize.sh tissuemosaic-app OUT_DIR
# Passes when a pixel in the middle of the 3D view, after the resize, is the view's dark background or the model,
# not the light grey of an undrawn widget.
set -u
app=$1 out=$2
mkdir -p "$out"
"$app" --demo --demo-frames 20 --demo-size 320x180 --start --device cpu > "$out/app.log" 2>&1 &
app_pid=$!
trap 'kill $app_pid 2>/dev/null' EXIT
window=
for _ in $(seq 300); do
  window=$(xdotool search --name "TissueMosaic" 2>/dev/null | head -n 1)
  [ -n "$window" ] && break
  sleep 0.1
done
[ -n "$window" ] || { echo "FAIL: no window"; exit 1; }
sleep 0.5  # before the first render of the view: the case that stayed grey
xdotool windowsize "$window" 1600 1000 && xdotool windowmove "$window" 0 0
sleep 15
import -window root "$out/after-resize.png" || { echo "FAIL: no screenshot"; exit 1; }
# A pixel in the middle of the 3D view (right of the 545 px module panel, in the upper part above the video).
rgb=$(convert "$out/after-resize.png" -crop 1x1+1100+250 -format '%[fx:int(255*r)] %[fx:int(255*g)] %[fx:int(255*b)]' info:)
read -r red green blue <<< "$rgb"
echo "3D view pixel after the resize: $red $green $blue"
if [ $((red + green + blue)) -ge 600 ]; then
  echo "FAIL: the 3D view is not drawn after the resize (light grey), see $out/after-resize.png"
  exit 1
fi
echo "view after resize: PASS"
