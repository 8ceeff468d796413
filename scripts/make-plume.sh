#!/usr/bin/env bash
# Writes scenes/plume.nvdb, the smoke plume of scenes/plume.json: a
# procedural density grid (src/tools/volume_shapes.h) written with NanoVDB's
# own builder by wavepath-volume, uncompressed.
#
#   scripts/make-plume.sh [BUILD_DIR] [HEIGHT]
set -euo pipefail
src=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$src/build}
height=${2:-96}
cmake --build "$build" --target wavepath-volume >/dev/null
"$build/wavepath-volume" plume "$src/scenes/plume.nvdb" "$height"
echo "wrote $src/scenes/plume.nvdb ($(stat -c %s "$src/scenes/plume.nvdb") bytes, $height voxels tall)"
