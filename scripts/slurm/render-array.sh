#!/usr/bin/env bash
# An sbatch job array that renders one scene in sample ranges, one range per
# task: task i of TASKS renders samples [i*SPP/TASKS, (i+1)*SPP/TASKS) into
# OUTDIR/part-i.exr. A task checkpoints as it goes and resumes its own
# checkpoint, so a task that was killed, preempted or requeued continues
# where it stopped when it runs again, and the part it leaves is the one an
# uninterrupted task would have left: the merge stays exact. Run
# scripts/slurm/merge.sh after all tasks (submit.sh chains the two).
#
#   sbatch --array=0-3 scripts/slurm/render-array.sh TASKS SPP OUTDIR SCENE [render options]
#
# The render options go after this script's own (a --checkpoint-every
# among them replaces its 30s). A task that fails (a lost GPU exits 75, a
# full disk 3, scancel 143) keeps what its checkpoint holds: submit it again
# (--array=i) and it goes on from there.
#
# The wavepath binary: $WAVEPATH, else `wavepath` on PATH, else
# build/wavepath under the directory sbatch was run from.
#SBATCH --job-name=wavepath-part
#SBATCH --cpus-per-task=1
#SBATCH --output=slurm-%A_%a.out
set -euo pipefail
if [ $# -lt 4 ] || [ -z "${SLURM_ARRAY_TASK_ID:-}" ]; then
  echo "usage: sbatch --array=0-(TASKS-1) $0 TASKS SPP OUTDIR SCENE [render options]" >&2
  exit 2
fi
tasks=$1 spp=$2 out=$3 scene=$4
shift 4
task=$SLURM_ARRAY_TASK_ID
if [ "$task" -ge "$tasks" ]; then
  echo "task $task of an array of $tasks: nothing to render" >&2
  exit 2
fi
wavepath=${WAVEPATH:-$(command -v wavepath || echo "${SLURM_SUBMIT_DIR:-.}/build/wavepath")}
begin=$((task * spp / tasks))
end=$(((task + 1) * spp / tasks))
mkdir -p "$out/checkpoints"
checkpoint="$out/checkpoints/part-$task.exr"
# exec: wavepath itself receives Slurm's SIGTERM, writes its checkpoint and
# exits with 143, so the task shows as failed and can be rerun.
exec "$wavepath" render "$scene" --spp "$spp" --samples "$begin:$end" -q \
  -o "$out/part-$task.png" --exr "$out/part-$task.exr" \
  --checkpoint "$checkpoint" --resume "$checkpoint" --checkpoint-every 30s \
  -t "${SLURM_CPUS_PER_TASK:-1}" "$@"
