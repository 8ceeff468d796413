#!/usr/bin/env bash
# `wavepath compare` as a user meets it: exit 0 when two renders agree, 1 when
# they differ, 2 on bad input with one line on stderr; and the HTML report as
# a real browser (headless Chromium) shows it.
# Usage: compare_cli.sh WAVEPATH TEST_DATA_DIR
set -u
wavepath=$1
data=$2
source "$(dirname "$0")/testlib.sh"

# Two independent CPU renders of one scene, and one of another size.
"$wavepath" render "$data/quad-light.json" --cpu --spp 64 --seed 1 -q -o "$work/a.png"
"$wavepath" render "$data/quad-light.json" --cpu --spp 64 --seed 2 -q -o "$work/b.png"
"$wavepath" render "$data/quad-light.json" --cpu --spp 4 --resolution 8 8 -q -o "$work/small.png"

"$wavepath" compare --images "$work/a.exr" "$work/b.exr" --report "$work/report" >"$work/out" 2>&1
rc=$?
check "stored renders agree: exit 0 and AGREE" $([ $rc -eq 0 ] && grep -q '^AGREE' "$work/out"; echo $?)
check "report written" $([ -s "$work/report/index.html" ]; echo $?)

"$wavepath" compare "$data/quad-light.json" --a cpu --b cpu --spp 64 --plant-bias 1.05 -q >"$work/out" 2>&1
rc=$?
check "planted 5% bias: exit 1 and DIFFER" $([ $rc -eq 1 ] && grep -q '^DIFFER' "$work/out"; echo $?)

"$wavepath" compare "$data/quad-light.json" --a gpu --b cpu --spp 64 -q >"$work/out" 2>&1
rc=$?
check "GPU against CPU on the command line: exit 0" $([ $rc -eq 0 ]; echo $?)

bad "missing EXR" "missing.exr" -- "$wavepath" compare --images "$work/missing.exr" "$work/b.exr"
bad "images of different sizes" "differ in size" -- "$wavepath" compare --images "$work/a.exr" "$work/small.exr"
bad "not an EXR" "not an OpenEXR file" -- "$wavepath" compare --images "$work/a.png" "$work/b.exr"
bad "scene and images together" "needs one of" -- "$wavepath" compare "$data/furnace.json" --images "$work/a.exr" "$work/b.exr"
bad "unknown kernel variant" "unknown kernel variant \"tpu\"" -- "$wavepath" compare "$data/furnace.json" --a tpu
"$wavepath" compare "$data/furnace.json" --a gpu-oneray --b gpu --spp 16 -q >"$work/out" 2>&1
check "one kernel variant against another: exit 0" $?
bad "an --alpha out of range" "--alpha" -- "$wavepath" compare --images "$work/a.exr" "$work/b.exr" --alpha 2

# Against a reference without variance (a course's *-ref.png): measured,
# judged by tolerances. The same scene is within them; a render of the
# light alone at twice its power is beyond; PNGs and EXRs alike.
"$wavepath" compare --reference "$work/a.png" "$work/b.png" >"$work/out" 2>&1
rc=$?
check "--reference: another render of the scene is WITHIN, exit 0" $([ $rc -eq 0 ] && grep -q '^WITHIN: mean / reference' "$work/out"; echo $?)
"$wavepath" compare --reference "$work/a.exr" "$work/b.exr" --tolerance 0.05 0.2 >"$work/out" 2>&1
check "--reference reads EXRs" $?
"$wavepath" render "$data/quad-light.json" --cpu --spp 64 --seed 3 -q -o "$work/dim.exr" --max-bounces 0
"$wavepath" compare --reference "$work/a.exr" "$work/dim.exr" >"$work/out" 2>&1
rc=$?
check "--reference: the light alone is BEYOND, exit 1" $([ $rc -eq 1 ] && grep -q '^BEYOND' "$work/out"; echo $?)
bad "--reference of another size" "differ in size" -- "$wavepath" compare --reference "$work/a.png" "$work/small.png"
bad "--reference missing" "missing-ref.png" -- "$wavepath" compare --reference "$work/missing-ref.png" "$work/a.png"
bad "--reference and a scene together" "needs one of" -- "$wavepath" compare "$data/furnace.json" --reference "$work/a.png" "$work/b.png"
bad "an unknown --curve" "--curve" -- "$wavepath" compare --reference "$work/a.png" "$work/b.png" --curve gamma

# The report in a real browser: every embedded image decodes, and it renders.
if command -v chromium >/dev/null; then
  flags=(--headless --no-sandbox --disable-gpu --disable-quic --no-first-run --disable-background-networking
         --disable-component-update --disable-sync --window-size=1280,900)
  timeout 120 chromium "${flags[@]}" --user-data-dir="$work/chrome1" --dump-dom "file://$work/report/index.html" \
    >"$work/dom" 2>/dev/null
  check "Chromium decodes all 4 report images" $(grep -q 'data-images-decoded="4/4"' "$work/dom"; echo $?)
  check "Chromium shows the verdict" $(grep -q 'class="verdict AGREE"' "$work/dom"; echo $?)
  timeout 120 chromium "${flags[@]}" --user-data-dir="$work/chrome2" --screenshot="$work/shot.png" \
    "file://$work/report/index.html" >/dev/null 2>&1
  size=$(od -An -tu1 -j16 -N8 "$work/shot.png" 2>/dev/null | awk '{print $3*256+$4 "x" $7*256+$8}')
  check "screenshot is 1280x900 (got $size)" $([ "$size" = "1280x900" ]; echo $?)
  check "screenshot is not blank" $([ "$(stat -c %s "$work/shot.png" 2>/dev/null || echo 0)" -gt 20000 ]; echo $?)
else
  fail "chromium is not installed (scripts/install-deps.sh installs it)"
fi

finish
