#!/usr/bin/env bash
# Submits a render as a Slurm job array of TASKS sample ranges and the merge
# job that runs after all of them; prints both job ids. Extra sbatch options
# (a partition, a time limit, --gres=gpu:1 ...) go in SBATCH_OPTIONS.
#
#   scripts/slurm/submit.sh TASKS SPP OUTDIR IMAGE.png SCENE [render options]
set -euo pipefail
if [ $# -lt 5 ]; then
  echo "usage: $0 TASKS SPP OUTDIR IMAGE.png SCENE [render options]" >&2
  exit 2
fi
here=$(cd "$(dirname "$0")" && pwd)
tasks=$1 spp=$2 out=$3 image=$4 scene=$5
shift 5
mkdir -p "$out"
# shellcheck disable=SC2086
array=$(sbatch --parsable ${SBATCH_OPTIONS:-} --array=0-$((tasks - 1)) --output="$out/slurm-%A_%a.out" \
  "$here/render-array.sh" "$tasks" "$spp" "$out" "$scene" "$@")
array=${array%%;*}
# shellcheck disable=SC2086
merge=$(sbatch --parsable ${SBATCH_OPTIONS:-} --dependency=afterok:"$array" --output="$out/slurm-%j.out" \
  "$here/merge.sh" "$out" "$image")
merge=${merge%%;*}
echo "render array $array (tasks 0-$((tasks - 1))), merge $merge"
