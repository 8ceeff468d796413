#!/usr/bin/env bash
# Full renders at equal settings, side by side: wavepath's kernels on the
# default Vulkan device, wavepath's CPU reference, and Blender's Cycles on the
# CPU (scripts/cycles_baseline.py; skipped when blender is not installed:
# `apt-get install blender`). Cornell box and Cornell dragon, 512x512, 64 spp,
# at most 8 bounces; ROUNDS interleaved rounds, medians of wall time.
# Usage: scripts/bench-render.sh [BUILD_DIR] [ROUNDS]   (default: build 3)
set -euo pipefail
build=${1:-build}
rounds=${2:-3}
cd "$(dirname "$0")/.."
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
threads=$(nproc)
echo "machine: $threads cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)"
"$build/wavepath" devices | sed -n 2p
have_blender=0
command -v blender >/dev/null && have_blender=1

# seconds of one run: wavepath's summary line ("... in 12.3 s on ...") or Cycles' line.
wavepath_seconds() { sed -n 's/.*max bounces, \([0-9.]*\) s on .*/\1/p'; }
median() { sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }

for scene in cornell-box cornell-dragon; do
  : >"$out/gpu" && : >"$out/cpu" && : >"$out/cycles"
  for _ in $(seq "$rounds"); do
    "$build/wavepath" render "scenes/$scene.json" --spp 64 --max-bounces 8 -o "$out/g.png" 2>&1 | wavepath_seconds >>"$out/gpu"
    "$build/wavepath" render "scenes/$scene.json" --spp 64 --max-bounces 8 -o "$out/c.png" --cpu 2>&1 | wavepath_seconds >>"$out/cpu"
    if [ $have_blender = 1 ]; then
      blender -b --factory-startup --python scripts/cycles_baseline.py -- "scenes/assets/$scene.obj" "$out/b.png" \
        512 512 64 8 "$threads" 2>/dev/null | sed -n 's/^cycles: \([0-9.]*\) s.*/\1/p' >>"$out/cycles"
    fi
  done
  samples=$((512 * 512 * 64))
  for who in gpu cpu cycles; do
    [ -s "$out/$who" ] || continue
    m=$(median <"$out/$who")
    printf '%-15s %-8s median %7.2f s  %6.3f Msamples/s  (runs: %s)\n' "$scene" "$who" "$m" \
      "$(awk -v s="$samples" -v m="$m" 'BEGIN { print s / m / 1e6 }')" "$(tr '\n' ' ' <"$out/$who")"
  done
done
