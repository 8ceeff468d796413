#!/usr/bin/env bash
# The cost of partial renders: for each size, a plain render of 4 samples per
# pixel against the same samples as 4 parts of one sample each (--samples)
# merged by `wavepath merge`: wall times, peak memory and file sizes. Prints
# a Markdown table (docs/benchmarks.md, "Partial renders").
# Usage: scripts/bench-partial.sh BUILD_DIR [SIZE...]   (default sizes: 512 4096)
# Render options for every render (e.g. --cpu: lavapipe's 128 MiB storage
# buffers hold the accumulators of 2048x2048 at most) in RENDER_OPTIONS.
set -euo pipefail
build=${1:?usage: $0 BUILD_DIR [SIZE...]}
shift
[ $# -gt 0 ] && sizes=("$@") || sizes=(512 4096)
wavepath="$build/wavepath"
scene="$(cd "$(dirname "$0")/.." && pwd)/scenes/cornell-box.json"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
measure() {  # measure NAME COMMAND...: appends "NAME seconds MiB" to $work/times
  local name=$1
  shift
  /usr/bin/time -f "$name %e %M" -a -o "$work/times" "$@" >/dev/null
}
mib() { awk -v b="$(stat -c %s "$1")" 'BEGIN { printf "%.1f", b / 1048576 }'; }
echo "| size | plain render | its EXR | 4 parts (sum) | a part's EXR | merge | merged EXR | merge's peak memory |"
echo "| --- | --- | --- | --- | --- | --- | --- | --- |"
for s in "${sizes[@]}"; do
  rm -f "$work/times"
  # shellcheck disable=SC2086
  measure plain "$wavepath" render "$scene" -r "$s" "$s" --spp 4 ${RENDER_OPTIONS:-} -q -o "$work/plain.png"
  for i in 0 1 2 3; do
    # shellcheck disable=SC2086
    measure part "$wavepath" render "$scene" -r "$s" "$s" --spp 4 --samples "$i:$((i + 1))" ${RENDER_OPTIONS:-} -q -o "$work/part-$i.png"
  done
  measure merge "$wavepath" merge "$work"/part-*.exr -o "$work/merged.png" -q
  plain=$(awk '$1 == "plain" {print $2}' "$work/times")
  parts=$(awk '$1 == "part" {t += $2} END {print t}' "$work/times")
  merge=$(awk '$1 == "merge" {print $2}' "$work/times")
  memory=$(awk '$1 == "merge" {printf "%.0f", $3 / 1024}' "$work/times")
  echo "| ${s}x${s} | ${plain} s | $(mib "$work/plain.exr") MiB | ${parts} s | $(mib "$work/part-0.exr") MiB | ${merge} s | $(mib "$work/merged.exr") MiB | ${memory} MiB |"
done
