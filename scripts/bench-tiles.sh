#!/usr/bin/env bash
# Images larger than a device's buffers hold, rendered in tiles: the Cornell
# box at 1 spp at each size (default 2048x2048, the largest lavapipe holds in
# one tile, and 7680x4320, 8K UHD), whole commands (loading, the kernels'
# creation, the render, the PNG and the EXR), with peak memory from
# /usr/bin/time, and each time against the first size's scaled by pixels.
# Prints a Markdown table (docs/benchmarks.md, "Tiles").
# Usage: scripts/bench-tiles.sh BUILD_DIR [WxH...] [-- render options]
set -euo pipefail
build=${1:?usage: $0 BUILD_DIR [WxH...] [-- render options]}
shift
sizes=()
while [ $# -gt 0 ] && [ "$1" != "--" ]; do sizes+=("$1"); shift; done
[ $# -gt 0 ] && shift
[ ${#sizes[@]} -gt 0 ] || sizes=(2048x2048 7680x4320)
scene="$(cd "$(dirname "$0")/.." && pwd)/scenes/cornell-box.json"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs); $("$build/wavepath" devices | sed -n 2p)"
echo "| size | pixels | time s | peak memory MiB | time / first size's scaled by pixels |"
echo "| --- | --- | --- | --- | --- |"
first=""
for s in "${sizes[@]}"; do
  w=${s%x*}
  h=${s#*x}
  /usr/bin/time -f "%e %M" -o "$work/time" "$build/wavepath" render "$scene" -r "$w" "$h" --spp 1 -q -o "$work/out.png" "$@" >/dev/null
  read -r seconds kib <"$work/time"
  pixels=$((w * h))
  [ -n "$first" ] || first="$seconds $pixels"
  ratio=$(awk -v t="$seconds" -v p="$pixels" -v f="$first" 'BEGIN { split(f, a, " "); printf "%.2f", t / (a[1] * p / a[2]) }')
  echo "| ${w}x${h} | $pixels | $seconds | $((kib / 1024)) | $ratio |"
done
