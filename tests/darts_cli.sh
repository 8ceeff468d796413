#!/usr/bin/env bash
# darts on the command line: test files of every kind run by `wavepath test`
# (and by `wavepath render`, as darts runs them) on the GPU and the CPU
# reference, writing the course's images beside the file; a failing test
# exits 1 and is named, an unreadable one exits 2; and the output formats
# darts saves, picked by -o's extension or darts' -f FORMAT.
# Usage: darts_cli.sh WAVEPATH TEST_DATA_DIR
set -u
wavepath=$(realpath "$1")
data=$(realpath "$2")
source "$(dirname "$0")/testlib.sh"
cp "$data"/darts/*.json "$work/"

for kind in materials surfaces intersection; do
  "$wavepath" test "$work/test_$kind.json" >"$work/out" 2>&1
  check "test_$kind.json passes on the GPU (exit 0)" $?
  grep -q "Passed all" "$work/out"
  check "test_$kind.json: says all passed" $?
done
"$wavepath" test --cpu "$work/test_surfaces.json" >"$work/out" 2>&1
check "test_surfaces.json passes on the CPU reference" $?
for f in diffuse-sampled.png diffuse-sampled.exr diffuse-pdf.png diffuse-pdf.exr diffuse-scatter-sampled.png group-pdf.exr; do
  check "wrote $f beside the file" $([ -s "$work/$f" ]; echo $?)
done
check "a scatter test writes no pdf, as in darts" $([ ! -e "$work/diffuse-scatter-pdf.png" ]; echo $?)
check "the images are the grid's size times up samples (64x32 x 4)" \
  $(python3 -c "import struct,sys; d=open('$work/diffuse-sampled.png','rb').read(24); sys.exit(struct.unpack('>II', d[16:24]) != (256, 128))"; echo $?)
"$wavepath" render "$work/test_intersection.json" >"$work/out" 2>&1
check "render runs a test file instead of rendering it" $([ $? -eq 0 ] && grep -q "Testing surface intersection" "$work/out"; echo $?)

"$wavepath" test "$work/test_failing.json" >"$work/out" 2>"$work/err"
rc=$?
check "a failing test: exit 1" $([ $rc -eq 1 ]; echo $?)
check "names the test that failed, and why" $(grep -q '"glass-has-no-density".*is_specular' "$work/err"; echo $?)
check "and the count" $(grep -q "Failed 1/2 tests" "$work/err"; echo $?)
"$wavepath" test "$work/test_unreadable.json" >"$work/out" 2>"$work/err"
rc=$?
check "an unreadable test: exit 2, the others still run" $([ $rc -eq 2 ] && grep -q "fine" "$work/out"; echo $?)
check "the typo gets a suggestion" $(grep -q '/tests/1/type.*did you mean "sample material"' "$work/err"; echo $?)
check "a photon map test with a flat transform names it" $(grep -q "/tests/2/transform/scale: scale factors must be non-zero" "$work/err"; echo $?)
"$wavepath" test "$work/test_photon_map.json" >"$work/out" 2>"$work/err"
rc=$?
check "photon map tests (k nearest and fixed radius) pass, writing darts' images" \
  $([ $rc -eq 0 ] && grep -q "Integrals of analytic PDF" "$work/out" && [ -s "$work/ellipse-nearest-photon-density.png" ] && [ -s "$work/tilted-fixed-radius-pdf.exr" ]; echo $?)
bad "a scene given to test" "holds no darts tests" -- "$wavepath" test "$data/quad-light.json"
mkdir "$work/readonly" && cp "$work/test_failing.json" "$work/readonly/" && chmod 555 "$work/readonly"
if [ -w "$work/readonly" ]; then
  pass "a test file in a folder it cannot write to (skipped: root writes anywhere)"
else
  bad "a test file in a folder it cannot write to" "the output directory is not writable" -- "$wavepath" test "$work/readonly/test_failing.json"
fi
chmod 755 "$work/readonly"

# Output formats, by extension.
scene="$data/quad-light.json"
for ext in png jpg bmp tga hdr pfm exr; do
  "$wavepath" render "$scene" --spp 2 -r 24 16 -q -o "$work/img.$ext"
  check "-o img.$ext writes it" $([ $? -eq 0 ] && [ -s "$work/img.$ext" ]; echo $?)
done
check "the JPEG is a JPEG" $(head -c 2 "$work/img.jpg" | od -An -tx1 | grep -q "ff d8"; echo $?)
check "the BMP is a BMP" $([ "$(head -c 2 "$work/img.bmp")" = BM ]; echo $?)
check "the HDR is Radiance" $(head -c 10 "$work/img.hdr" | grep -q "#?RADIANCE"; echo $?)
check "the PFM is colour, little-endian, 24x16" \
  $([ "$(head -n 3 "$work/img.pfm" | tr '\n' ' ')" = "PF 24 16 -1.0 " ] && [ "$(stat -c %s "$work/img.pfm")" -eq $((14 + 24 * 16 * 12)) ]; echo $?)
check "a .jpg render keeps its EXR of statistics beside it" $([ -s "$work/img.exr" ]; echo $?)
(cd "$work" && "$wavepath" render "$scene" --spp 2 -r 24 16 -q -f hdr)
check "darts' -f hdr: SCENE.hdr and SCENE.exr" $([ -s "$work/quad-light.hdr" ] && [ -s "$work/quad-light.exr" ]; echo $?)
bad "an unknown extension" "img.gif: the output image's extension must name one of" -- "$wavepath" render "$scene" -o "$work/img.gif"
bad "an extension against --format" "contradicts --format" -- "$wavepath" render "$scene" --format png -o "$work/img.exr"

finish
