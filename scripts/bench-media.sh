#!/usr/bin/env bash
# The cost of participating media on the kernels: one scene (a floor, a ball
# and an area light, 320x240, 64 spp, at most 8 bounces) without media and
# with each kind of medium the kernels handle: the kernels compiled for media
# on the scene without (its ball bounds a vacuum: what media cost a scene
# that has nothing for them to do), a thin haze filling the scene
# (the camera's medium), the same with null particles (ratio-tracked shadow
# rays), a dense chromatic fog inside an interface ball, and a milky medium
# inside a glass ball. ROUNDS interleaved rounds on the default Vulkan device
# (or --cpu), medians of the render time; samples per second and the ratio
# to the scene without media. WIDTH and HEIGHT change the image's size (a
# GPU needs more than 320x240 to fill it).
# Usage: [VARIANTS="clear haze ..."] [WIDTH=w HEIGHT=h] scripts/bench-media.sh [BUILD_DIR] [ROUNDS] [extra render options]   (default: build 3)
set -euo pipefail
build=${1:-build}
rounds=${2:-3}
shift $(( $# > 2 ? 2 : $# ))
cd "$(dirname "$0")/.."
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

white='{"type": "lambertian", "albedo": 0.6}'
glass='{"type": "dielectric", "ior": 1.33}'
declare -A camera=([clear]="" [vacuum]="" [haze]=', "medium": "haze"' [haze-null]=', "medium": "haze"' [fog-ball]="" [milk-glass]="")
declare -A ball=(
  [clear]="\"material\": $white"
  [vacuum]="\"material\": $white, \"interior\": \"nothing\""
  [haze]="\"material\": $white"
  [haze-null]="\"material\": $white"
  [fog-ball]='"material": null, "interior": "fog"'
  [milk-glass]="\"material\": $glass, \"interior\": \"milk\""
)
declare -A media=(
  [clear]=''
  [vacuum]='{"type": "vacuum", "name": "nothing"}'
  [haze]='{"type": "homogeneous", "name": "haze", "albedo": 0.8, "total": 0.15}'
  [haze-null]='{"type": "homogeneous", "name": "haze", "albedo": 0.8, "total": 0.3, "real fraction": 0.5}'
  [fog-ball]='{"type": "homogeneous", "name": "fog", "albedo": [0.9, 0.8, 0.6], "total": [2, 3, 4], "phase function": {"type": "henyey-greenstein", "g": 0.5}}'
  [milk-glass]='{"type": "homogeneous", "name": "milk", "albedo": 0.95, "total": 6}'
)
variants=${VARIANTS:-"clear vacuum haze haze-null fog-ball milk-glass"}
width=${WIDTH:-320}
height=${HEIGHT:-240}
for v in $variants; do
  cat >"$out/$v.json" <<SCENE
{"camera": {"transform": {"from": [0, 1.2, 3.2], "at": [0, 0.5, 0], "up": [0, 1, 0]}, "vfov": 35, "resolution": [$width, $height]${camera[$v]}},
 "sampler": {"samples": 64}, "integrator": {"type": "path tracer mis", "max bounces": 8}, "background": 0.1,
 "media": [${media[$v]}],
 "surfaces": [{"type": "quad", "size": 8, "material": $white, "transform": {"rotate": [-90, 1, 0, 0]}},
              {"type": "sphere", "radius": 0.6, ${ball[$v]}, "transform": {"translate": [0, 0.6, 0]}},
              {"type": "quad", "size": 2, "material": {"type": "diffuse_light", "emit": 4},
               "transform": [{"rotate": [90, 1, 0, 0]}, {"translate": [0, 3, 0.5]}]}]}
SCENE
done

. scripts/bench-rounds.sh
bench_rounds "$build" "$rounds" "$out" "$variants" $((width * height * 64)) "$@"
