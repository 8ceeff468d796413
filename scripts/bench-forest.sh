#!/usr/bin/env bash
# Instancing at scale: two glTF forests from scripts/gen-forest.py against the
# flat Cornell dragon (100k triangles). The forest: a million trees (default)
# of three meshes that hold a million triangles between them (3 x 10^11
# placed), jittered, turned and scaled; the grid (--grid): the same number of
# one 20k-triangle tree on every grid point, as a new user would place them.
# Per scene: what `wavepath info` reports (load, BVH build, GPU memory, the
# instances) and that process's peak resident memory from /usr/bin/time; then
# one `wavepath bench --raycast` of all three at 1024x1024 with the default
# variant, or the variants VARIANTS names (camera rays; a bounce from each
# hit, a shadow ray), against Embree where built in, and each forest's rate
# as a fraction of the flat dragon's in that run (issue 54's target: camera
# rays at least a quarter).
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
python3 "$root/scripts/gen-forest.py" "$work/grid.gltf" --instances "$instances" --triangles 20000 --grid
scenes=("$work/forest.gltf" "$work/grid.gltf" "$root/scenes/cornell-dragon.json")
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs); $("$build/wavepath" devices | sed -n 2p)"
echo
echo "| scene | triangles placed | unique | load s | build s | GPU scene MiB | top level / meshes MiB | peak resident MiB |"
echo "| --- | --- | --- | --- | --- | --- | --- | --- |"
for scene in "${scenes[@]}"; do
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
"$build/wavepath" bench --raycast --scenes "$(IFS=,; echo "${scenes[*]}")" --variants "${VARIANTS:-gpu}" --resolution 1024 1024 \
  --repeats 3 --out "$work/rays.json" "$@" >"$work/rays.txt"
python3 - "$work/rays.json" <<'PY'
import json, os, sys
rows = json.load(open(sys.argv[1]))["raycast"]
rate = {(os.path.basename(r["scene"]), r["rays"], r["variant"]): r for r in rows if r.get("check_passed")}
flat = "cornell-dragon.json"
print("| scene | variant | Mrays/s camera / bounce / shadow | Embree | walk steps a ray | of the flat dragon's rate (camera; Embree's) |")
print("| --- | --- | --- | --- | --- | --- |")
for (scene, _, variant) in sorted({(s, 0, v) for (s, _, v) in rate}, key=lambda k: (k[0] == flat, k[0], k[2])):
    sets = [rate.get((scene, s, variant)) for s in ("primary", "bounce", "shadow")]
    fmt = lambda key, f: " / ".join(f % r[key] if r and key in r else "-" for r in sets)
    cam, base = sets[0], rate.get((flat, "primary", variant))
    share = "-"
    if cam and base and scene != flat:
        share = "%.3f" % (cam["mrays_per_second"] / base["mrays_per_second"])
        if "embree_mrays_per_second" in cam:
            share += "; %.3f" % (cam["embree_mrays_per_second"] / base["embree_mrays_per_second"])
    print(f"| {scene} | `{variant}` | {fmt('mrays_per_second', '%.2f')} | {fmt('embree_mrays_per_second', '%.2f')} | "
          f"{fmt('cpu_walk_steps_per_ray', '%.1f')} | {share} |")
PY
grep -E "disagrees" "$work/rays.txt" || true
