#!/usr/bin/env bash
# The job that merges the parts of scripts/slurm/render-array.sh into one
# image, once every task has succeeded (submit it with
# --dependency=afterok:ARRAY_JOB, as submit.sh does). `wavepath merge`
# refuses parts of different renders, overlaps and missing ranges, so a
# merge can never silently lose samples.
#
#   sbatch --dependency=afterok:JOB scripts/slurm/merge.sh OUTDIR IMAGE.png
#SBATCH --job-name=wavepath-merge
#SBATCH --cpus-per-task=1
#SBATCH --output=slurm-%j.out
set -euo pipefail
if [ $# -ne 2 ]; then
  echo "usage: sbatch --dependency=afterok:JOB $0 OUTDIR IMAGE.png" >&2
  exit 2
fi
wavepath=${WAVEPATH:-$(command -v wavepath || echo "${SLURM_SUBMIT_DIR:-.}/build/wavepath")}
exec "$wavepath" merge "$1"/part-*.exr -o "$2"
