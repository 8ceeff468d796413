#!/usr/bin/env bash
# How wavepath scales from 100 thousand to 10 million triangles: grids of 1 to
# 100 dragons (scripts/make-scale-scenes.py). Per scene: load and BVH build
# time, GPU memory per triangle (BVH included), and the GPU time of a render
# at 256x256, 4 spp, 8 bounces (Vulkan timestamps, so loading, building and
# uploading are not counted).
# Usage: scripts/bench-scale.sh [BUILD_DIR] [COUNT ...]   (default: build 1 3 10 30 100)
set -euo pipefail
build=${1:-build}
shift || true
cd "$(dirname "$0")/.."
scenes=$(mktemp -d)
trap 'rm -rf "$scenes"' EXIT
scripts/make-scale-scenes.py "$scenes" "$@" >/dev/null
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs); $("$build/wavepath" devices | sed -n 2p)"
printf '%-12s %12s %8s %9s %10s %9s %14s\n' scene triangles "load s" "build s" "Mtri/s" "B/tri" "GPU s/Msample"
for scene in $(ls "$scenes"/dragons-*.json | sort -t- -k2 -n); do
  info=$("$build/wavepath" info "$scene")
  tris=$(echo "$info" | sed -n 's/^primitives *\([0-9]*\) triangles.*/\1/p')
  load=$(echo "$info" | sed -n 's/^load *\([0-9.]*\) s.*/\1/p')
  build_s=$(echo "$info" | sed -n 's/.*built in \([0-9.]*\) s (\([0-9.]*\) Mprims.*/\1/p')
  rate=$(echo "$info" | sed -n 's/.*built in [0-9.]* s (\([0-9.]*\) Mprims.*/\1/p')
  bytes=$(echo "$info" | sed -n 's/.*MiB (\([0-9.]*\) bytes per primitive.*/\1/p')
  gpu=$("$build/wavepath" render "$scene" -r 256 256 --spp 4 --max-bounces 8 --stage-times -q -o "$scenes/out.png" 2>&1 |
    sed -n 's/^total *\([0-9.]*\).*/\1/p')
  per=$(awk -v g="$gpu" 'BEGIN { print g / (256 * 256 * 4 / 1e6) }')
  printf '%-12s %12s %8s %9s %10s %9s %14.2f\n' "$(basename "$scene" .json)" "$tris" "$load" "$build_s" "$rate" "$bytes" "$per"
done
