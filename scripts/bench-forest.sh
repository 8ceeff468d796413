#!/usr/bin/env bash
# Instancing at scale: a glTF forest from scripts/gen-forest.py (default a
# million trees of three meshes that hold a million triangles between them,
# placing 3 x 10^11) against the flat Cornell dragon (100k triangles). Per
# scene: what `wavepath info` reports (load, BVH build, GPU memory, the
# instances), that process's peak resident memory from /usr/bin/time, and
# the rays per second of `wavepath bench --raycast` at 1024x1024 with the
# default variant, or the variants VARIANTS names (primary: camera rays; a
# bounce from each hit, a shadow ray).
# Prints Markdown tables (docs/benchmarks.md, "Instancing").
# Usage: scripts/bench-forest.sh BUILD_DIR [INSTANCES] [TRIANGLES] [-- bench options, e.g. --device 0]
set -euo pipefail
build=${1:?usage: $0 BUILD_DIR [INSTANCES] [TRIANGLES] [-- bench options]}
shift
instances=1000000
triangles=1000000
if [ $# -gt 0 ] && [ "$1" != "--" ]; then instances=$1; shift; fi
if [ $# -gt 0 ] && [ "$1" != "--" ]; then triangles=$1; shift; fi
[ $# -gt 0 ] && shift
root="$(cd "$(dirname "$0")/.." && pwd)"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
python3 "$root/scripts/gen-forest.py" "$work/forest.gltf" --instances "$instances" --triangles "$triangles"
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs); $("$build/wavepath" devices | sed -n 2p)"
echo
echo "| scene | triangles placed | unique | load s | build s | GPU scene MiB | top level / meshes MiB | peak resident MiB |"
echo "| --- | --- | --- | --- | --- | --- | --- | --- |"
for scene in "$work/forest.gltf" "$root/scenes/cornell-dragon.json"; do
  /usr/bin/time -f "%M" -o "$work/rss" "$build/wavepath" info "$scene" >"$work/info"
  field() { sed -n "$1" "$work/info"; }
  placed=$(field 's/^instances .*unique triangles place \([0-9]*\) .*/\1/p')
  unique=$(field 's/^instances .*mesh.*: \([0-9]*\) unique triangles.*/\1/p')
  world=$(field 's/^primitives *\([0-9]*\) triangles.*/\1/p')
  levels=$(field 's/^instances .*top level \([0-9.]*\) MiB.*trees and triangles \([0-9.]*\) MiB.*/\1 \/ \2/p')
  echo "| $(basename "$scene") | $((world + ${placed:-0})) | $((world + ${unique:-0})) | $(field 's/^load *\([0-9.]*\) s.*/\1/p') |" \
    "$(field 's/.*built in \([0-9.]*\) s.*/\1/p') | $(field 's/^GPU scene *\([0-9.]*\) MiB.*/\1/p') | ${levels:--} |" \
    "$(($(cat "$work/rss") / 1024)) |"
done
echo
for scene in "$work/forest.gltf" "$root/scenes/cornell-dragon.json"; do
  echo "$(basename "$scene"):"
  "$build/wavepath" bench --raycast --scenes "$scene" --variants "${VARIANTS:-gpu}" --resolution 1024 1024 --repeats 3 "$@" |
    grep -E "^ +(primary|bounce|shadow|rays) " || true
done
