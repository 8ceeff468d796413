#!/usr/bin/env bash
# The cost of glTF's PBR extensions on the kernels: a sphere filling most of
# the frame on a floor under an area light, in plain metal-rough and in each
# layer or parameter the extensions add (KHR_materials_specular's tint, a
# clear coat, a sheen, a coat over a sheen; thin-walled transmission,
# KHR_materials_volume's refraction into an absorbing volume, and
# KHR_materials_iridescence's thin film, KHR_materials_anisotropy, KHR_materials_dispersion,
# KHR_materials_diffuse_transmission, KHR_materials_volume_scatter's particles), 320x240, 64 spp, at most 8
# bounces, on the default Vulkan device (or --cpu). ROUNDS interleaved
# rounds, medians of the render time; samples per second and the ratio to
# plain metal-rough.
# Usage: [VARIANTS="plain volume ..."] scripts/bench-layers.sh [BUILD_DIR] [ROUNDS] [extra render options]   (default: build 3)
set -euo pipefail
build=${1:-build}
rounds=${2:-3}
shift $(( $# > 2 ? 2 : $# ))
cd "$(dirname "$0")/.."
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

base='{"type": "metal_rough", "base_color": [0.7, 0.2, 0.1], "metallic": 0, "roughness": 0.5'
declare -A material=(
  [plain]="$base, \"name\": \"m\"}"
  [specular]="$base, \"name\": \"m\", \"specular\": 0.7, \"specular_color\": [1.5, 1, 0.5]}"
  [clearcoat]="{\"type\": \"clearcoat\", \"name\": \"m\", \"roughness\": 0.1, \"base\": $base}}"
  [sheen]="{\"type\": \"sheen\", \"name\": \"m\", \"color\": [0.8, 0.6, 0.7], \"roughness\": 0.4, \"base\": $base}}"
  [coat+sheen]="{\"type\": \"clearcoat\", \"name\": \"m\", \"roughness\": 0.1, \"base\": {\"type\": \"sheen\", \"color\": [0.8, 0.6, 0.7], \"roughness\": 0.4, \"base\": $base}}}"
  [thin-glass]="$base, \"name\": \"m\", \"transmission\": 1}"
  [volume]="$base, \"name\": \"m\", \"transmission\": 1, \"volume\": {\"attenuation_color\": [0.9, 0.6, 0.3], \"attenuation_distance\": 1}}"
  [iridescence]="$base, \"name\": \"m\", \"iridescence\": {\"factor\": 1, \"ior\": 1.3}}"
  [anisotropy]="$base, \"name\": \"m\", \"anisotropy\": {\"strength\": 0.8, \"rotation\": 0.5}}"
  [dispersion]="$base, \"name\": \"m\", \"transmission\": 1, \"volume\": {\"attenuation_color\": [0.9, 0.6, 0.3], \"attenuation_distance\": 1, \"dispersion\": 1}}"
  [diffuse-transmission]="$base, \"name\": \"m\", \"diffuse_transmission\": 0.6, \"diffuse_transmission_color\": [0.9, 0.7, 0.4]}"
  [scatter]="$base, \"name\": \"m\", \"transmission\": 1, \"volume\": {\"attenuation_color\": [0.9, 0.6, 0.3], \"attenuation_distance\": 1, \"multiscatter_color\": [0.8, 0.6, 0.4]}}"
)
variants=${VARIANTS:-"plain specular clearcoat sheen coat+sheen thin-glass volume iridescence anisotropy dispersion diffuse-transmission scatter"}
for v in $variants; do
  cat >"$out/$v.json" <<SCENE
{"camera": {"transform": {"from": [0, 1.2, 3.2], "at": [0, 0.5, 0], "up": [0, 1, 0]}, "vfov": 35, "resolution": [320, 240]},
 "sampler": {"samples": 64}, "integrator": {"type": "path tracer mis", "max bounces": 8}, "background": 0.1,
 "materials": [{"type": "lambertian", "name": "floor", "albedo": 0.5}, ${material[$v]}],
 "surfaces": [{"type": "quad", "size": 8, "material": "floor", "transform": {"rotate": [-90, 1, 0, 0]}},
              {"type": "sphere", "radius": 0.6, "material": "m", "transform": {"translate": [0, 0.6, 0]}},
              {"type": "quad", "size": 2, "material": {"type": "diffuse_light", "emit": 4},
               "transform": [{"rotate": [90, 1, 0, 0]}, {"translate": [0, 3, 0.5]}]}]}
SCENE
done

. scripts/bench-rounds.sh
bench_rounds "$build" "$rounds" "$out" "$variants" $((320 * 240 * 64)) "$@"
