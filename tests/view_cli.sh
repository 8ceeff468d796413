#!/usr/bin/env bash
# `wavepath view` as a user meets it, in a real window on Xvfb with lavapipe
# (validation on, from the environment): a frame appears and is not blank;
# the screenshot equals the PNG the window writes; the scripted mode's EXR
# agrees with `render`'s; a mouse drag (XTEST through xdotool) moves the
# camera, D writes the camera file and `render -c` gives the image the window
# showed; ] doubles the samples; C renders a dragged cell as -p does; a
# resize renders at the new size; Tab renders the AOVs; a render stopped in
# the window finishes with the `render --resume` it prints; Esc writes the
# image and exits 0; bad input and no display give one line and exit 2. Skips (77) where xvfb-run, xdotool or
# ImageMagick is missing; CI installs them (scripts/install-deps.sh).
# Usage: view_cli.sh WAVEPATH SCENES_DIR
set -u
wavepath=$(realpath "$1")
scene=$(realpath "$2/cornell-box.json")
data=$(realpath "$(dirname "$0")/data")
if ! "$wavepath" view --keys >/dev/null 2>&1; then
  echo "SKIP: this wavepath was built without GLFW (libglfw3-dev)"
  exit 77
fi
for tool in xvfb-run xdotool import compare identify; do
  if ! command -v "$tool" >/dev/null; then
    echo "SKIP: $tool is missing (Debian: xvfb, xdotool, imagemagick)"
    exit 77
  fi
done
if [ -z "${WAVEPATH_UNDER_XVFB:-}" ]; then
  # Without a display first, then everything else on a fresh Xvfb.
  env -u DISPLAY -u WAYLAND_DISPLAY "$wavepath" view "$scene" >/tmp/wavepath-view-nodisplay.$$ 2>&1
  rc=$?
  lines=$(wc -l </tmp/wavepath-view-nodisplay.$$)
  cat /tmp/wavepath-view-nodisplay.$$
  rm -f /tmp/wavepath-view-nodisplay.$$
  if [ $rc -ne 2 ] || [ "$lines" -ne 1 ]; then
    echo "FAIL no display: exit 2 with one line (got exit $rc, $lines lines)"
    exit 1
  fi
  echo "ok   no display: exit 2 with one line"
  exec xvfb-run -a -s "-screen 0 1024x768x24" env WAVEPATH_UNDER_XVFB=1 bash "$0" "$@"
fi
source "$(dirname "$0")/testlib.sh"
cd "$work"
size=(-r 160 120)

# title_reaches WINDOW TEXT: waits (at most 120 s) for the window's title to hold TEXT.
title_reaches() {
  for _ in $(seq 1200); do
    xdotool getwindowname "$1" 2>/dev/null | grep -qF -- "$2" && return 0
    sleep 0.1
  done
  return 1
}
# open_window OUTPUT [view options]: starts the viewer, sets $pid and $win.
open_window() {
  local out=$1
  shift
  "$wavepath" view "$scene" "${size[@]}" -o "$out" "$@" >"$work/view.out" 2>"$work/view.err" &
  pid=$!
  win=$(timeout 120 xdotool search --sync --name '^wavepath: cornell-box' 2>/dev/null | head -1)
}
# close_window NAME: Esc, then the viewer must exit 0 with nothing on stderr.
close_window() {
  xdotool windowfocus --sync "$win" key Escape 2>/dev/null
  wait "$pid"
  local rc=$?
  check "$1: Esc exits 0, and validation reports nothing" $([ $rc -eq 0 ] && [ ! -s "$work/view.err" ]; echo $?)
  [ -s "$work/view.err" ] && cat "$work/view.err"
}

# Bad input, as `render` reports it: one line, exit 2, no window left open.
bad "a missing scene" "missing.json" -- "$wavepath" view "$work/missing.json"
bad "an EXR as the window's image" "8-bit image" -- "$wavepath" view "$scene" -o "$work/out.exr"
printf '40 30 1.3\n' >short_cam_settings.txt
bad "a camera file of 3 numbers" "short_cam_settings.txt" -- "$wavepath" view "$scene" -c short_cam_settings.txt

"$wavepath" view --help >out 2>&1
check "view --help lists every key" $(grep -q '^Esc ' out && grep -q '^C ' out && grep -q '^Tab ' out; echo $?)

# Scripted: N samples in the window, the files `render` writes, exit 0.
"$wavepath" view "$scene" "${size[@]}" --spp 4 --exit-when-done -o scripted.png -q >out 2>err
rc=$?
check "scripted: exit 0, PNG and EXR written" $([ $rc -eq 0 ] && [ -s scripted.png ] && [ -s scripted.exr ] && [ ! -s err ]; echo $?)
"$wavepath" render "$scene" "${size[@]}" --spp 4 -o render.png -q
"$wavepath" compare --images scripted.exr render.exr >out 2>&1
check "scripted: its EXR agrees with render's" $?

# Adaptive sampling (CS184's -a) in the window: the rate image beside it, as render writes one.
"$wavepath" view "$scene" "${size[@]}" --spp 32 -a 8 0.05 --exit-when-done -o adaptive.png -q >out 2>err
rc=$?
check "scripted adaptive: exit 0, the rate image written" $([ $rc -eq 0 ] && [ -s adaptive_rate.png ] && [ ! -s err ]; echo $?)
"$wavepath" render "$scene" "${size[@]}" --spp 32 -a 8 0.05 -o adaptive-render.png -q
"$wavepath" compare --images adaptive.exr adaptive-render.exr >out 2>&1
check "scripted adaptive: its EXR agrees with render's" $?

# A frame appears, is not blank, and is the image the window saves.
open_window shown.png --spp 2
check "a window titled after the scene appears" $([ -n "$win" ]; echo $?)
title_reaches "$win" "| 2/2 spp"
check "the title counts the samples up to 2/2" $?
sleep 0.5
import -window "$win" shot.png
close_window "first window"
spread=$(identify -format '%[fx:standard_deviation]' shot.png 2>/dev/null)
check "the screenshot is not blank (deviation $spread)" $(awk -v s="$spread" 'BEGIN { exit !(s > 0.02) }'; echo $?)
differing=$(compare -metric AE -fuzz 0.5% shot.png shown.png null: 2>&1)
check "the screenshot equals the PNG the window wrote (pixels differing: $differing)" $([ "$differing" = "0" ]; echo $?)

# Input: a drag orbits, D writes the camera file, ] doubles the samples.
open_window dragged.png --spp 2
title_reaches "$win" "| 2/2 spp"
xdotool windowfocus --sync "$win" mousemove --window "$win" 60 60 mousedown 1 sleep 0.2 mousemove --window "$win" 80 64 sleep 0.2 \
  mousemove --window "$win" 100 70 sleep 0.2 mouseup 1 2>/dev/null
sleep 0.5
title_reaches "$win" "| 2/2 spp"
xdotool windowfocus --sync "$win" key d 2>/dev/null
sleep 0.5
check "D writes cornell-box_cam_settings.txt" $([ -s cornell-box_cam_settings.txt ]; echo $?)
xdotool windowfocus --sync "$win" key bracketright 2>/dev/null
title_reaches "$win" "| 4/4 spp"
check "] doubles the samples per pixel: the title reaches 4/4" $?
close_window "dragged window"
check "the window's EXR holds samples 0:4" $([ "$(exr_attr dragged.exr wavepath:samples)" = "0:4" ]; echo $?)
"$wavepath" render "$scene" "${size[@]}" -c cornell-box_cam_settings.txt --spp 4 -o from-file.png -q
"$wavepath" compare --images dragged.exr from-file.exr >out 2>&1
check "render -c with the camera file agrees with the window's image" $?
"$wavepath" compare --images dragged.exr render.exr >out 2>&1
check "the drag changed the view (the scene's own camera's image differs)" $([ $? -eq 1 ]; echo $?)

# C and a drag: the cell alone, saved as -p renders it.
open_window cell.png --spp 2
title_reaches "$win" "| 2/2 spp"
xdotool windowfocus --sync "$win" key c mousemove --window "$win" 40 30 mousedown 1 sleep 0.2 mousemove --window "$win" 70 55 sleep 0.2 \
  mousemove --window "$win" 100 80 sleep 0.2 mouseup 1 2>/dev/null
title_reaches "$win" "| 60x50 | 2/2 spp"
check "C and a drag render the cell: the title reaches 60x50, 2/2" $?
close_window "cell window"
again=$(sed -n 's/^view: render it again with: wavepath //p' "$work/view.out")
check "the cell's command line is -p's, rows from the bottom" $(echo "$again" | grep -q -- '-p 40 40 60 50'; echo $?)
eval "\"\$wavepath\" $again -o cell-render.png -q" >out 2>&1
"$wavepath" compare --images cell.exr cell-render.exr >out 2>&1
check "render -p with that command agrees with the window's cell" $?

# The scene reloads when its file changes; a broken edit leaves the scene
# as it was, with one line on stderr, and the window goes on.
cp "$data/quad-light.json" edited.json
"$wavepath" view edited.json -r 64 64 --spp 2 -o edited.png >"$work/view.out" 2>"$work/view.err" &
pid=$!
win=$(timeout 120 xdotool search --sync --name '^wavepath: edited' 2>/dev/null | head -1)
title_reaches "$win" "| 2/2 spp"
echo '{ "camera": ' >edited.json
sleep 1.5
check "a broken edit is reported and the scene as it was stays" $(grep -q 'the scene as it was stays' "$work/view.err" && kill -0 "$pid"; echo $?)
sed 's/"albedo": \[0.6, 0.5, 0.4\]/"albedo": [0.2, 0.7, 0.2]/' "$data/quad-light.json" >edited.json
sleep 1.5
title_reaches "$win" "| 2/2 spp"
xdotool windowfocus --sync "$win" key Escape 2>/dev/null
wait "$pid"
rc=$?
check "an edit reloads the scene, keeping the window: exit 0" $([ $rc -eq 0 ] && grep -q '^view: reloaded' "$work/view.out"; echo $?)
"$wavepath" render edited.json -r 64 64 --spp 2 -o edited-render.png -q
"$wavepath" compare --images edited.exr edited-render.exr >out 2>&1
check "the window saved the edited scene's image" $?

# A resize renders at the window's new size; Tab to the albedo renders the
# first hits' layers from then on, and the EXR holds them.
open_window resized.png --spp 2
title_reaches "$win" "| 2/2 spp"
xdotool windowsize "$win" 200 150 2>/dev/null
title_reaches "$win" "| 200x150 | 2/2 spp"
check "a resize renders at the window's size: the title reaches 200x150, 2/2" $?
xdotool windowfocus --sync "$win" key Tab 2>/dev/null
title_reaches "$win" "| albedo"
title_reaches "$win" "| 2/2 spp"
close_window "resized window"
check "the saved image has the window's size" $([ "$(identify -format '%wx%h' resized.png 2>/dev/null)" = "200x150" ]; echo $?)
check "after Tab the EXR holds the first hits' layers" $(exr_attr resized.exr wavepath:settings | grep -q 'aovs=albedo,normal,depth'; echo $?)

# A render stopped in the window continues with the command it prints.
"$wavepath" view "$scene" -r 64 48 --spp 2048 -o stopped.png >"$work/view.out" 2>"$work/view.err" &
pid=$!
win=$(timeout 120 xdotool search --sync --name '^wavepath: cornell-box' 2>/dev/null | head -1)
for _ in $(seq 1200); do
  xdotool getwindowname "$win" 2>/dev/null | grep -q '| [1-9][0-9]*/2048 spp' && break
  sleep 0.1
done
close_window "stopped window"
again=$(sed -n 's/^view: finish it with: wavepath //p' "$work/view.out")
check "a stopped window prints how to finish it with --resume" $(echo "$again" | grep -q -- '--resume stopped.exr'; echo $?)
eval "\"\$wavepath\" $again -o finished.png -q" >out 2>&1
rc=$?
check "render --resume finishes it: exit 0, samples 0:2048, complete" \
  $([ $rc -eq 0 ] && [ "$(exr_attr finished.exr wavepath:samples)" = "0:2048" ] && [ "$(exr_attr finished.exr wavepath:status)" = "complete" ]; echo $?)

finish
