#!/usr/bin/env bash
# The figures docs/benchmarks.md records for the first-light renderer:
# Cornell box at 512x512, 64 spp, 8 bounces on the default Vulkan device and
# on the CPU reference, and the BVH build of the dragon.
# Usage: scripts/bench-first-light.sh [BUILD_DIR]   (default: build)
set -euo pipefail
build=${1:-build}
cd "$(dirname "$0")/.."
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)"
"$build/wavepath" devices | head -2
for i in 1 2 3; do
  "$build/wavepath" render scenes/cornell-box.json --spp 64 --max-bounces 8 -o "$out/gpu.png"
done
for i in 1 2 3; do
  "$build/wavepath" render scenes/cornell-box.json --spp 64 --max-bounces 8 -o "$out/cpu.png" --cpu
done
for i in 1 2 3; do
  "$build/wavepath" info scenes/dragon.json | grep -E "^BVH|^GPU"
done
