#!/usr/bin/env bash
# A render as a Slurm job array against one process rendering the same
# samples: the wall time from submission to the merged image, and the one
# process's. On a one-node cluster of the machine's own cores
# (scripts/slurm/cluster-up.sh) no speed-up is expected: the point is that
# the array's image is the same. On a real cluster, run it on a login node
# with SBATCH_OPTIONS naming the partition (and --gres=gpu:1 for GPUs); the
# one-process figure is then the login node's.
# Usage: scripts/bench-slurm.sh BUILD_DIR [TASKS] [SPP] [render options...]
#        (default: 4 tasks, 1024 spp, the Cornell box at 256x256 on the CPU reference)
set -euo pipefail
build=$(cd "${1:?usage: $0 BUILD_DIR [TASKS] [SPP] [render options]}" && pwd)
tasks=${2:-4}
spp=${3:-1024}
shift $(($# < 3 ? $# : 3))
options=("$@")
[ ${#options[@]} -gt 0 ] || options=(-r 256 256 --cpu)
src=$(cd "$(dirname "$0")/.." && pwd)
scene="$src/scenes/cornell-box.json"
work=$(mktemp -d "${TMPDIR:-/tmp}/wavepath-bench-slurm.XXXXXX")
trap 'rm -rf "$work"' EXIT
chmod 755 "$work"
export WAVEPATH="$build/wavepath"

t0=$(date +%s.%N)
ids=$("$src/scripts/slurm/submit.sh" "$tasks" "$spp" "$work/parts" "$work/array.png" "$scene" "${options[@]}")
merge=${ids##* }
while [ -n "$(squeue -h -j "$merge" -o %T 2>/dev/null)" ]; do sleep 0.2; done
t1=$(date +%s.%N)
[ -s "$work/array.exr" ] || { echo "the merge job wrote no image; see $work/parts/slurm-*.out" >&2; trap - EXIT; exit 1; }
"$WAVEPATH" render "$scene" --spp "$spp" -q -o "$work/one.png" "${options[@]}"
t2=$(date +%s.%N)
verdict=$("$WAVEPATH" compare --images "$work/array.exr" "$work/one.exr" | head -1 | cut -c1-6)
awk -v a="$(echo "$t1 - $t0" | awk '{print $1 - $3}')" -v b="$(echo "$t2 - $t1" | awk '{print $1 - $3}')" \
  -v t="$tasks" -v s="$spp" -v v="$verdict" -v o="${options[*]}" \
  'BEGIN { printf "| %d-task array | %.1f s | one process | %.1f s | speed-up %.2fx | %d spp, %s | compare: %s |\n", t, a, b, b / a, s, o, v }'
