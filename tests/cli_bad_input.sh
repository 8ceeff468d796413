#!/usr/bin/env bash
# The command line on bad input, as a user meets it: one line on stderr naming
# the file and the problem, a non-zero exit, no crash, and no image left behind.
# Usage: cli_bad_input.sh WAVEPATH TEST_DATA_DIR
set -u
wavepath=$1
data=$2
source "$(dirname "$0")/testlib.sh"

# expect_error NAME EXIT_CODE "TEXT1|TEXT2|..." -- COMMAND...
expect_error() {
  local name=$1 code=$2 texts=$3
  shift 4
  rm -f "$work"/out.* "$work"/*.tmp*
  "$@" >"$work/stdout" 2>"$work/stderr"
  local rc=$?
  local problems=""
  [ "$rc" -eq "$code" ] || problems+=" exit $rc (want $code);"
  [ "$rc" -lt 128 ] || problems+=" crashed (signal $((rc - 128)));"
  [ "$(wc -l <"$work/stderr")" -eq 1 ] || problems+=" stderr has $(wc -l <"$work/stderr") lines (want 1);"
  grep -q '^wavepath: error: ' "$work/stderr" || problems+=" stderr does not start with 'wavepath: error:';"
  local IFS='|'
  for t in $texts; do grep -qF -- "$t" "$work/stderr" || problems+=" message lacks '$t';"; done
  if ls "$work"/out.* "$work"/*.tmp* >/dev/null 2>&1; then problems+=" an output file was left behind;"; fi
  if [ -n "$problems" ]; then
    fail "$name:$problems"
    sed 's/^/    stderr: /' "$work/stderr"
  else
    pass "$name: $(cat "$work/stderr")"
  fi
}

out="$work/out.png"
expect_error "missing scene file" 2 "no-such.json|no such file" -- "$wavepath" render "$data/no-such.json" -o "$out" --spp 1
expect_error "not a scene file" 2 "bad-image.png|not a scene file wavepath reads" -- "$wavepath" render "$data/bad-image.png" -o "$out" --spp 1
expect_error "JSON syntax error" 2 "bad-syntax.json:4:24|JSON syntax error" -- "$wavepath" render "$data/bad-syntax.json" -o "$out" --spp 1
expect_error "unknown key" 2 "bad-unknown-key.json|/camera/fov|unknown key \"fov\"" -- "$wavepath" render "$data/bad-unknown-key.json" -o "$out"
expect_error "unknown material type" 2 "bad-material-type.json|/surfaces/0/material/type|velvet" -- "$wavepath" render "$data/bad-material-type.json" -o "$out"
expect_error "negative radius" 2 "bad-radius.json|/surfaces/0/radius" -- "$wavepath" render "$data/bad-radius.json" -o "$out"
expect_error "an image the host's memory cannot hold (-r), before the scene loads" 2 \
  "a 8000x4000 image needs about|more than WAVEPATH_HOST_MEMORY_MIB's 1000 MiB" -- \
  env WAVEPATH_HOST_MEMORY_MIB=1000 "$wavepath" render "$data/no-such.json" -r 8000 4000 -o "$out"
printf '{ "camera": { "resolution": [3000, 2000] }, "surfaces": [] }' >"$work/big.json"
expect_error "an image the host's memory cannot hold (the scene's size)" 2 "a 3000x2000 image needs about|more than" -- \
  env WAVEPATH_HOST_MEMORY_MIB=64 "$wavepath" render "$work/big.json" -o "$out"
expect_error "OBJ index out of range" 2 "bad-index.obj:4|vertex 99" -- "$wavepath" render "$data/mesh-bad-index.json" -o "$out"
expect_error "OBJ negative index out of range" 2 "bad-negative.obj:4|vertex -7" -- "$wavepath" render "$data/mesh-bad-negative.json" -o "$out"
expect_error "OBJ that does not parse" 2 "bad-token.obj:4|not a vertex index" -- "$wavepath" render "$data/mesh-bad-token.json" -o "$out"
expect_error "missing OBJ" 2 "no-such-mesh.obj|no such file|mesh-missing.json" -- "$wavepath" render "$data/mesh-missing.json" -o "$out"
expect_error "output in no image format" 2 "out.gif|extension must name one of|png, jpg" -- "$wavepath" render "$data/furnace.json" -o "$work/out.gif"
expect_error "output directory missing" 2 "no-dir/out.png|does not exist" -- "$wavepath" render "$data/furnace.json" -o "$work/no-dir/out.png"
# Benchmark and convergence results: refused before the (long) runs begin.
expect_error "bench JSON directory missing" 2 "no-dir/r.json|does not exist" -- "$wavepath" bench --scenes "$data/furnace.json" --out "$work/no-dir/r.json"
expect_error "ray-casting CSV directory missing" 2 "no-dir/r.csv|does not exist" -- "$wavepath" bench --raycast --scenes "$data/furnace.json" --csv "$work/no-dir/r.csv"
expect_error "a node stride smaller than a node" 2 "--node-stride 48: a gpu node takes 80 bytes" -- "$wavepath" bench --simt --scenes "$data/furnace.json" --variants gpu --resolution 8 8 --node-stride 48
expect_error "convergence CSV directory missing" 2 "no-dir/c.csv|does not exist" -- "$wavepath" convergence "$data/furnace.json" --csv "$work/no-dir/c.csv"
expect_error "bad option value" 2 "spp" -- "$wavepath" render "$data/furnace.json" -o "$out" --spp 0
expect_error "no Vulkan device" 3 "no Vulkan device" -- env VK_DRIVER_FILES=/nonexistent/icd.json VK_ICD_FILENAMES=/nonexistent/icd.json "$wavepath" render "$data/furnace.json" -o "$out" --spp 1
expect_error "no such device" 2 "--device no-such-gpu" -- "$wavepath" render "$data/furnace.json" -o "$out" --spp 1 --device no-such-gpu
expect_error "unknown integrator" 2 "--integrator|bdpt" -- "$wavepath" render "$data/furnace.json" -o "$out" --integrator bdpt
expect_error "unknown sampler" 2 "--sampler|sobol" -- "$wavepath" render "$data/furnace.json" -o "$out" --sampler sobol
expect_error "missing texture image" 2 "no-such.png|no such file|/materials/0/albedo" -- "$wavepath" render "$data/bad-texture.json" -o "$out"
# A valid 20000x20000 PNG (black, RGB) as a texture: too large, with its size
# and the limit, read from its header before any decoding. Written in a
# moment: its rows compressed once as a block that resets the compressor,
# repeated, with the checksum of them all.
python3 - "$work/huge.png" <<'PY'
import struct, sys, zlib
w = h = 20000
rows = 100
chunk = (b'\0' * (1 + 3 * w)) * rows
c = zlib.compressobj(9)
first = c.compress(chunk) + c.flush(zlib.Z_FULL_FLUSH)
block = c.compress(chunk) + c.flush(zlib.Z_FULL_FLUSH)
end = c.flush()[:-4]
adler = 1
for _ in range(h // rows):
    adler = zlib.adler32(chunk, adler)
data = first + block * (h // rows - 1) + end + struct.pack('>I', adler)
def part(kind, body):
    return struct.pack('>I', len(body)) + kind + body + struct.pack('>I', zlib.crc32(kind + body))
open(sys.argv[1], 'wb').write(b'\x89PNG\r\n\x1a\n' + part(b'IHDR', struct.pack('>IIBBBBB', w, h, 8, 2, 0, 0, 0)) + part(b'IDAT', data) + part(b'IEND', b''))
PY
printf '{ "materials": [ { "type": "lambertian", "name": "a", "albedo": { "type": "image", "filename": "huge.png" } } ],
  "surfaces": [ { "type": "sphere", "material": "a" } ] }' >"$work/huge.json"
expect_error "a 20000x20000 PNG texture" 2 "huge.png|too large: 20000x20000 pixels|more than the 33554432" -- "$wavepath" render "$work/huge.json" -o "$out"
# A darts mesh whose file is no OBJ (a path gone wrong to /etc/passwd, say)
# yields no triangles: a warning names it, and the render goes on.
printf 'root:x:0:0:root:/root:/bin/bash\ndaemon:x:1:1:daemon:/usr/sbin:/usr/sbin/nologin\n' >"$work/passwd"
printf '{ "surfaces": [ { "type": "mesh", "filename": "passwd", "material": { "type": "lambertian" } },
  { "type": "sphere", "material": { "type": "lambertian" } } ] }' >"$work/not-obj.json"
"$wavepath" render "$work/not-obj.json" -r 8 6 --spp 1 --cpu -q -o "$work/not-obj.png" 2>"$work/stderr"
check "a mesh file that is no OBJ: exit 0, one warning naming it and where the scene names it" \
  $([ $? -eq 0 ] && [ "$(wc -l <"$work/stderr")" -eq 1 ] && grep -qF "warning: $work/passwd: no triangles (is it an OBJ file?), loaded by $work/not-obj.json at /surfaces/0/filename" "$work/stderr"; echo $?)

# CS184 users' short options are aliases of wavepath's own.
rm -f "$work"/out.*
"$wavepath" render "$data/features/materials.json" -f "$out" -s 2 -m 1 -r 12 8 -t 1 -b 0.05 -d 4 -l 2 -H --cpu --quiet && [ -s "$work/out.png" ]
check "CS184 options -f -s -m -r -t -b -d -l -H are accepted" $?
"$wavepath" render "$data/features/materials.json" -f "$out" -s 2 -m 1 -r 12 8 -t 1 --cpu | grep -q "12x8, 2 spp, 1 max bounces"
check "CS184 options take effect" $?
expect_error "file that is no image" 2 "bad-image.png|not a PNG, JPEG, BMP, TGA, Radiance HDR or OpenEXR image|/materials/0/albedo" -- "$wavepath" render "$data/bad-image.json" -o "$out"
expect_error "OBJ normal index out of range" 2 "bad-normal-index.obj|normal or texture coordinate" -- "$wavepath" render "$data/mesh-bad-normal-index.json" -o "$out"
expect_error "too many light samples" 2 "light-samples" -- "$wavepath" render "$data/furnace.json" -o "$out" -l 65
expect_error "-H against another integrator" 2 "-H|contradict" -- "$wavepath" render "$data/furnace.json" -o "$out" -H --integrator "path tracer nee"
expect_error "--spectral against --rgb" 2 "--spectral|--rgb|contradict" -- "$wavepath" render "$data/furnace.json" -o "$out" --spectral --rgb
expect_error "adaptive batch not whole" 2 "--adaptive|batch" -- "$wavepath" render "$data/furnace.json" -o "$out" --adaptive 2.5 0.05
expect_error "environment map missing" 2 "no-such-sky.hdr|no such file|--env" -- "$wavepath" render "$data/furnace.json" -o "$out" -e "$data/no-such-sky.hdr"
expect_error "unknown variant for info" 2 "nope" -- "$wavepath" info "$data/furnace.json" --variant nope
expect_error "megakernel with more bounces than its loop budget allows" 3 "megakernel" -- \
  "$wavepath" render "$data/furnace.json" -o "$out" --variant gpu-mega -m 500

# Adaptive sampling writes CS184's sample-rate image beside the render.
rm -f "$work"/out*
"$wavepath" render "$data/features/integrators.json" -f "$out" -s 64 -a 16 0.05 --quiet && [ -s "$work/out.png" ] && [ -s "$work/out_rate.png" ]
check "-a BATCH TOL writes out.png and out_rate.png" $?
rm -f "$work"/out*

# And the good path writes both images, on the GPU and on the CPU.
for mode in gpu cpu; do
  rm -f "$work"/out.*
  extra=()
  [ "$mode" = cpu ] && extra=(--cpu)
  "$wavepath" render "$data/furnace.json" -o "$out" --spp 2 --quiet "${extra[@]}" && [ -s "$work/out.png" ] && [ -s "$work/out.exr" ]
  check "render on the $mode writes out.png and out.exr" $?
done
"$wavepath" devices | grep -q "type "
check "devices lists at least one device" $?
"$wavepath" info "$data/furnace.json" --variant gpu-bvh2 | grep -q "^BVH  *binary"
check "info --variant gpu-bvh2 builds the binary tree" $?
expect_error "info --kernels for the cpu reference" 2 "--kernels|cpu" -- "$wavepath" info "$data/furnace.json" --kernels --variant cpu
expect_error "info --device without --kernels" 2 "--device|--kernels" -- "$wavepath" info "$data/furnace.json" --device 0
# The driver's statistics of each kernel, where the driver reports them
# (NVIDIA does; lavapipe 22.3 does not, and says so).
"$wavepath" info "$data/furnace.json" --kernels >"$work/stdout" 2>"$work/stderr"
rc=$?
if [ $rc -eq 0 ]; then
  check "info --kernels lists the kernels with their statistics" $(grep -qE '^  extend \(.*\): .+;' "$work/stdout" &&
    grep -qE '^  shade \(' "$work/stdout"; echo $?)
else
  check "info --kernels on a driver without statistics: exit 3, one line naming the device" $([ $rc -eq 3 ] &&
    [ "$(wc -l <"$work/stderr")" -eq 1 ] && grep -q "reports no kernel statistics" "$work/stderr"; echo $?)
fi

# glTF: a model that reaches outside its folder, a truncated binary file, a
# camera it does not have; the generator of the test models writes what the
# repository holds; a model renders through the camera asked for.
mkdir -p "$work/model"
sed 's/"scene.bin"/"..\/secret.bin"/' "$data/gltf/external/scene.gltf" >"$work/model/scene.gltf"
cp "$data/gltf/external/scene.bin" "$work/secret.bin"
expect_error "glTF URI outside the model's folder" 2 "model/scene.gltf|secret.bin|inside its own folder" -- "$wavepath" render "$work/model/scene.gltf" -o "$out"
head -c 1000 "$data/gltf/textured.glb" >"$work/truncated.glb"
expect_error "truncated glb" 2 "truncated.glb|cannot read glTF" -- "$wavepath" render "$work/truncated.glb" -o "$out"
expect_error "unknown glTF camera" 2 "--camera side|textured.glb|1 \"persp\"" -- "$wavepath" render "$data/gltf/textured.glb" --camera side -o "$out"
"$wavepath" render "$data/gltf/textured.glb" --camera ortho -r 16 16 --spp 2 -q -o "$work/ortho.png"
check "an orthographic glTF camera renders" $([ -s "$work/ortho.png" ]; echo $?)
"$wavepath" render "$data/gltf/textured.glb" --camera persp -r 24 18 --spp 2 -q -o "$work/glb.png"
check "a .glb renders through --camera persp at the size asked" $([ -f "$work/glb.png" ] && [ "$(od -An -tu1 -j16 -N8 "$work/glb.png" | tr -s ' ')" = " 0 0 0 24 0 0 0 18" ]; echo $?)
# --env none takes the white sky of a model without lights away: every
# float of the PFM (a model lit by the sky alone) is 0.
"$wavepath" render "$data/gltf/textured.glb" --camera persp --env none -r 8 6 --spp 8 -q -o "$work/dark.pfm" 2>"$work/dark.err"
check "--env none: no line about the default sky" $([ ! -s "$work/dark.err" ]; echo $?)
check "--env none: a model lit only by the default sky renders black" \
  $(python3 -c "import struct,sys; d=open('$work/dark.pfm','rb').read(); h=d.split(b'\n',3); v=struct.unpack('<%df' % (8*6*3), h[3][:8*6*3*4]); sys.exit(any(v))"; echo $?)
"$wavepath" render "$data/gltf/textured.glb" --camera persp -r 8 6 --spp 8 -q -o "$work/sky.pfm" 2>"$work/sky.err"
check "the default sky, added, is named in one line on stderr with --env none" \
  $([ "$(wc -l <"$work/sky.err")" = 1 ] && grep -q "textured.glb: .*white sky.*--env none removes it" "$work/sky.err"; echo $?)
check "and without it the sky lights the model" \
  $(python3 -c "import struct,sys; d=open('$work/sky.pfm','rb').read(); h=d.split(b'\n',3); v=struct.unpack('<%df' % (8*6*3), h[3][:8*6*3*4]); sys.exit(not all(x > 0 for x in v))"; echo $?)
generator="$(cd "$(dirname "$0")/.." && pwd)/scripts/make-gltf-test-assets.py"
models="$(cd "$data/gltf" && pwd)"
(cd "$work" && mkdir -p gen && cd gen && python3 "$generator" && for f in box-room.gltf box-room.json textured.glb surface.glb mirror-bumps.glb lamp-room.glb labels.glb \
  external/scene.gltf external/scene.bin external/checker.png; do cmp -s "tests/data/gltf/$f" "$models/$f" || exit 1; done)
check "make-gltf-test-assets.py writes the models the repository holds" $?
# The README's glTF example: its generator writes what the repository holds, and it renders.
repo="$(cd "$(dirname "$0")/.." && pwd)"
(cd "$work" && rm -rf example && mkdir -p example/scenes/assets && cp "$repo/scenes/assets/spot.obj" example/scenes/assets/ && cd example &&
  python3 "$repo/scripts/make-gltf-example.py" && cmp -s scenes/spot.glb "$repo/scenes/spot.glb")
check "make-gltf-example.py writes the scenes/spot.glb the repository holds" $?
"$wavepath" render "$repo/scenes/spot.glb" --env "$repo/scenes/assets/sky.hdr" -r 32 24 --spp 2 -q -o "$work/spot.png"
check "scenes/spot.glb renders under an environment map" $([ -f "$work/spot.png" ]; echo $?)

# CS184's COLLADA scenes: bad files, then the course's command line with the scene last.
dae="$data/collada/cornell.dae"
size_of() { od -An -tu1 -j16 -N8 "$1" | tr -s ' '; }  # a PNG's width and height, as bytes
printf '<COLLADA>\n  <asset><up_axis>Z_UP</up_axis>\n</COLLADA>\n' >"$work/broken.dae"
expect_error "COLLADA malformed XML" 2 "broken.dae:3:|malformed XML" -- "$wavepath" render "$work/broken.dae" -f "$out"
sed 's/url="#ball-sphere"/url="#no-such-sphere"/' "$dae" >"$work/dangling.dae"
expect_error "COLLADA dangling url" 2 "dangling.dae:|#no-such-sphere|names no element" -- "$wavepath" render "$work/dangling.dae" -f "$out"
sed 's/target="#glass"/target="#floor-mesh"/' "$dae" >"$work/wrong-kind.dae"
expect_error "COLLADA target of the wrong kind" 2 "wrong-kind.dae:|names a <geometry>, not a <material>" -- "$wavepath" render "$work/wrong-kind.dae" -f "$out"
sed 's/<vcount>4<\/vcount>/<vcount>2<\/vcount>/' "$dae" >"$work/degenerate.dae"
expect_error "COLLADA degenerate polygon" 2 "degenerate.dae:|a polygon of 2 vertices" -- "$wavepath" render "$work/degenerate.dae" -f "$out"
expect_error "-p outside the frame" 2 "-p 790 0 20 20|inside the 800x600 frame" -- "$wavepath" render -s 1 -p 790 0 20 20 -f "$out" "$dae"
expect_error "--consistent-lights on a darts scene" 2 "--consistent-lights|furnace.json|not a CS184 scene" -- "$wavepath" render "$data/furnace.json" --consistent-lights -o "$out"
expect_error "--cs184 3-2 on a darts scene" 2 "--cs184 3-2|furnace.json|not a CS184 scene" -- "$wavepath" render "$data/furnace.json" --cs184 3-2 -o "$out"
expect_error "--cs184 with --consistent-lights" 2 "--consistent-lights|--cs184 3-2|choose one" -- "$wavepath" render --cs184 3-2 --consistent-lights -f "$out" "$dae"
expect_error "an unknown --cs184 skeleton" 2 "--cs184" -- "$wavepath" render --cs184 3-3 -f "$out" "$dae"
expect_error "missing camera settings file" 2 "no-such-camera.txt|cannot read" -- "$wavepath" render -c "$work/no-such-camera.txt" -f "$out" "$dae"
rm -f "$work"/cb*.png
"$wavepath" render -t 2 -s 2 -l 16 -m 6 -r 48 36 -f "$work/cb.png" "$dae" 2>/dev/null >/dev/null
check "CS184's command line: -t -s -l 16 -m -r -f, the .dae last, renders at the size asked" $([ "$(size_of "$work/cb.png")" = " 0 0 0 48 0 0 0 36" ]; echo $?)
"$wavepath" render -s 1 -p 100 50 16 12 -f "$work/cbcell.png" "$dae" -q && [ "$(size_of "$work/cbcell.png")" = " 0 0 0 16 0 0 0 12" ]
check "-p X Y DX DY renders one cell of the frame" $?
printf '60 40 1.33 0.1 100\n0.5 1 3 0 0.75 0\n1.4 0.1 3 0.3 60\n1 0 0 0 1 0 0 0 1\n800 600 824.2\n4.7 0\n' >"$work/cam.txt"
"$wavepath" render -s 1 -c "$work/cam.txt" -r 16 12 -f "$work/cbcam.png" "$dae" -q && [ -s "$work/cbcam.png" ]
check "-c reads a camera settings file" $?
"$wavepath" render -s 8 -a 4 0.5 -r 16 12 -f "$work/cbrate.png" "$dae" -q && [ -s "$work/cbrate_rate.png" ]
check "-a writes the rate image beside a .dae's render" $?
"$wavepath" render -s 4 -m 3 -H -r 16 12 -f "$work/cbh.png" --consistent-lights "$dae" -q && [ -s "$work/cbh.png" ]
check "-H and --consistent-lights render a .dae" $?
"$wavepath" render -s 4 -m 3 -r 16 12 -f "$work/cb32.png" --cs184 3-2 "$dae" -q && [ -s "$work/cb32.png" ]
check "--cs184 3-2 renders a .dae" $?

# A .dae's parts merge into the very PNG its whole render writes (CS184's
# tone curve); a part seen through another camera (-c) is refused.
for r in 0:2 2:4; do "$wavepath" render -s 4 -m 2 -r 20 15 --samples "$r" -f "$work/cbpart${r%:*}.png" --cpu -q "$dae"; done
"$wavepath" render -s 4 -m 2 -r 20 15 -f "$work/cbwhole.png" --cpu -q "$dae"
"$wavepath" merge "$work/cbpart0.exr" "$work/cbpart2.exr" -o "$work/cbmerged.png" -q && cmp -s "$work/cbmerged.png" "$work/cbwhole.png"
check "a .dae's merged parts give the PNG of its whole render" $?
"$wavepath" render -s 4 -m 2 -r 20 15 --samples 2:4 -c "$work/cam.txt" -f "$work/cbother.png" --cpu -q "$dae"
expect_error "merging a part of another view" 2 "cbother.exr|other settings|view" -- "$wavepath" merge "$work/cbpart0.exr" "$work/cbother.exr" -o "$work/out.png"

# Grid media: a .nvdb that is not one, named by a scene; the plume renders.
printf 'not a grid' >"$work/fake.nvdb"
cat >"$work/grid.json" <<EOF
{ "camera": { "transform": { "from": [0, 0, 5], "at": [0, 0, 0], "up": [0, 1, 0] }, "medium": "m" },
  "media": [ { "type": "nanovdb", "name": "m", "filename": "fake.nvdb" } ],
  "surfaces": [ { "type": "sphere", "radius": 1, "material": { "type": "lambertian" } } ] }
EOF
expect_error "a .nvdb that is not one" 2 "fake.nvdb|not a NanoVDB file|grid.json at /media/0" -- "$wavepath" render "$work/grid.json" -o "$out" --spp 1
"$wavepath" render "$(dirname "$0")/../scenes/plume.json" -r 24 32 --spp 2 -o "$work/plume.png" -q
check "scenes/plume.json renders" $([ -s "$work/plume.png" ]; echo $?)

# The scaling scenes' generator: usage without arguments, scenes that load.
scale="$(dirname "$0")/../scripts/make-scale-scenes.py"
"$scale" >/dev/null 2>&1
check "make-scale-scenes.py without an output folder: exit non-zero" $([ $? -ne 0 ]; echo $?)
"$scale" "$work/scale" 2 >/dev/null && "$wavepath" info "$work/scale/dragons-2.json" | grep -q "^primitives *200004 triangles"
check "make-scale-scenes.py writes a grid of dragons that loads" $?

finish
