#!/usr/bin/env bash
# The benchmark set for a real GPU, in one go: the device, the kernel variants
# on full renders of the Cornell box and the Cornell dragon (512x512, 64 spp,
# 8 bounces), ray casting on the four scenes of issue 5 at 1024x1024 and
# 4096x4096 rays (a large GPU needs many rays in flight), wall time of whole
# renders (setup included), and the 0.1 to 10 M triangle grid. Runs on any
# Vulkan device; on lavapipe it takes about an hour.
# Usage: scripts/bench-gpu.sh [BUILD_DIR] [OUT_DIR] [DEVICE]
#   (default: build, a temporary folder, the default device)
# Writes raycast-*.json, render.json/.csv and log.txt to OUT_DIR.
set -euo pipefail
build=$(realpath "${1:-build}")
out=${2:-$(mktemp -d)}
mkdir -p "$out" && out=$(realpath "$out")
device=${3:-}
cd "$(dirname "$0")/.."
dev=()
[ -n "$device" ] && dev=(--device "$device")
scenes=scenes/cornell-box.json,scenes/bunny.json,scenes/dragon.json,scenes/cornell-dragon.json

{
  echo "== machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)"
  "$build/wavepath" devices

  # The variants first: which one should be the default on GPUs is the open question.
  echo "== kernel variants, full renders 512x512, 64 spp"
  "$build/wavepath" bench "${dev[@]}" --scenes scenes/cornell-box.json,scenes/cornell-dragon.json \
    --resolution 512 512 --spp 64 --repeats 3 --out "$out/render.json" --csv "$out/render.csv"

  for res in 1024 4096; do
    echo "== ray casting, ${res}x${res} rays per set"
    "$build/wavepath" bench --raycast "${dev[@]}" --scenes "$scenes" --variants gpu,gpu-regstack,gpu-bvh2 \
      --resolution "$res" "$res" --repeats 5 --out "$out/raycast-$res.json"
  done

  echo "== whole renders (wall time, setup included), 512x512, 64 spp, 8 bounces"
  for scene in cornell-box cornell-dragon; do
    for _ in 1 2 3; do
      "$build/wavepath" render "scenes/$scene.json" "${dev[@]}" -r 512 512 --spp 64 --max-bounces 8 --stage-times \
        -o "$out/$scene.png" 2>&1 | grep -E "max bounces|^total"
    done
  done

  echo "== scaling"
  scripts/bench-scale.sh "$build" 1 10 100
} 2>&1 | tee "$out/log.txt"
