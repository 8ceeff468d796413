#!/usr/bin/env bash
# Delta tracking through a grid medium against a single majorant and against
# majorant grids of several cell counts: scenes/plume.json (the smoke plume
# of scenes/plume.nvdb, 96 voxels tall) at WIDTH x HEIGHT (default 240x320),
# 16 spp, with "majorant grid" 1 (darts' one majorant for the whole grid),
# 4, 8, 16, 32 and 64 cells per axis, and without the key (wavepath's
# default, about one cell per NanoVDB leaf). ROUNDS interleaved rounds on the
# default Vulkan device (or --cpu), medians of the render time; samples per
# second and the ratio to the single majorant.
# Usage: [VARIANTS="m1 m4 ..."] [WIDTH=w HEIGHT=h] scripts/bench-majorants.sh [BUILD_DIR] [ROUNDS] [extra render options]   (default: build 3)
set -euo pipefail
build=$(realpath "${1:-build}")
rounds=${2:-3}
shift $(( $# > 2 ? 2 : $# ))
cd "$(dirname "$0")/.."
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
variants=${VARIANTS:-"m1 m4 m8 m16 m32 m64 default"}
width=${WIDTH:-240}
height=${HEIGHT:-320}
cp scenes/plume.nvdb "$out/"
for v in $variants; do
  cells=${v#m}
  python3 -c '
import json, sys
cells, width, height = sys.argv[1:4]
scene = json.load(open("scenes/plume.json"))
scene["camera"]["resolution"] = [int(width), int(height)]
scene["sampler"]["samples"] = 16
if cells != "default":
    scene["media"][0]["majorant grid"] = int(cells)
json.dump(scene, sys.stdout)' "$cells" "$width" "$height" >"$out/$v.json"
done

. scripts/bench-rounds.sh
bench_rounds "$build" "$rounds" "$out" "$variants" $((width * height * 16)) "$@"
