#!/usr/bin/env bash
# Slurm job arrays on a one-node cluster brought up on this machine
# (scripts/slurm/cluster-up.sh): a 4-task array renders a scene in sample
# ranges; one task is killed while it renders (scancel: SIGTERM), leaves its
# checkpoint and is resubmitted alone; the merge job runs after every task
# succeeded (--dependency=afterok). The rerun task's part is the one an
# uninterrupted task leaves, byte for byte, and the merged image agrees with
# one process rendering the same samples. Then two tasks meet faults
# (WAVEPATH_FAULT: a lost device, a full disk), fail, keep their
# checkpoints, and finish when resubmitted.
# Where the daemons cannot start (not root, a container that forbids them)
# the test says so and is skipped (exit 77); on CI it must run.
# Usage: slurm_cli.sh WAVEPATH TEST_DATA_DIR SCRIPTS_DIR
set -u
wavepath=$1
data=$2
scripts=$3
source "$(dirname "$0")/testlib.sh"

if ! up=$(bash "$scripts/slurm/cluster-up.sh" 2>&1); then
  if [ "${CI:-}" = true ]; then
    fail "the one-node Slurm cluster must come up on CI: $up"
    finish
    exit 1
  fi
  echo "SKIP: no Slurm cluster here: $up"
  exit 77
fi
# A cluster this test brought up goes down with it.
case "$up" in *"already up"*) ;; *) trap 'bash "$scripts/slurm/cluster-down.sh"; rm -rf "$work"' EXIT ;; esac

# Waits (at most $2 seconds) until job $1 has left the queue.
wait_gone() {
  for _ in $(seq $(($2 * 5))); do
    [ -z "$(squeue -h -j "$1" -o %T 2>/dev/null)" ] && return 0
    sleep 0.2
  done
  return 1
}

scene="$data/features/materials.json"
opts=(-r 96 64 --cpu)
spp=4096  # each task of 4 takes seconds on one core: long enough to be killed while it renders
out="$work/parts"
chmod 755 "$work"
export WAVEPATH="$wavepath"
array=$(sbatch --parsable --array=0-3 --output="$work/slurm-%A_%a.out" "$scripts/slurm/render-array.sh" 4 $spp "$out" "$scene" "${opts[@]}")
check "the array is submitted" $([ -n "$array" ]; echo $?)

# Kill task 2 once it renders.
state=""
for _ in $(seq 600); do
  state=$(squeue -h -j "${array}_2" -o %T 2>/dev/null)
  [ "$state" = RUNNING ] && break
  sleep 0.2
done
check "task 2 runs (state $state)" $([ "$state" = RUNNING ]; echo $?)
sleep 1.5
scancel "${array}_2"
wait_gone "${array}_2" 60
check "killed, task 2 leaves its checkpoint, marked interrupted" \
  $([ "$(exr_attr "$out/checkpoints/part-2.exr" wavepath:status)" = "interrupted by SIGTERM" ]; echo $?)

# Resubmit task 2 alone; merge after the survivors and the rerun succeed.
rerun=$(sbatch --parsable --array=2 --output="$work/slurm-%A_%a.out" "$scripts/slurm/render-array.sh" 4 $spp "$out" "$scene" "${opts[@]}")
merge=$(sbatch --parsable --dependency=afterok:"${array}_0:${array}_1:${array}_3:${rerun}" --output="$work/slurm-merge.out" \
  "$scripts/slurm/merge.sh" "$out" "$work/merged.png")
wait_gone "$merge" 300
check "the merge job ran after every task and wrote the image" $([ -s "$work/merged.png" ] && [ -s "$work/merged.exr" ]; echo $?)
check "the merged file holds samples 0:$spp, complete" \
  $([ "$(exr_attr "$work/merged.exr" wavepath:samples)" = "0:$spp" ] && [ "$(exr_attr "$work/merged.exr" wavepath:status)" = complete ]; echo $?)

# The rerun task's part is the uninterrupted one, byte for byte.
"$wavepath" render "$scene" "${opts[@]}" --spp $spp --samples $((spp / 2)):$((spp * 3 / 4)) -t 1 -q -o "$work/task2.png" --exr "$work/task2.exr"
check "the rerun task's part equals an uninterrupted one" $(cmp -s "$out/part-2.exr" "$work/task2.exr"; echo $?)

# One process, the same samples.
"$wavepath" render "$scene" "${opts[@]}" --spp $spp -q -o "$work/single.png"
"$wavepath" compare --images "$work/merged.exr" "$work/single.exr" >"$work/compare" 2>&1
check "the merged image agrees with one process (wavepath compare)" $?

# Faults in tasks (WAVEPATH_FAULT, on their first run only): task 0, on
# lavapipe, loses its device at its 4th submission; task 1's disk fills at
# its 2nd file, a checkpoint. Each fails (75, 3) keeping its checkpoint;
# resubmitted, both finish, and the merge after them holds every sample.
faulty="$work/faulty-wavepath"
cat >"$faulty" <<WRAPPER
#!/usr/bin/env bash
if [ ! -e "$work/faulted-\$SLURM_ARRAY_TASK_ID" ]; then
  touch "$work/faulted-\$SLURM_ARRAY_TASK_ID"
  case \$SLURM_ARRAY_TASK_ID in 0) export WAVEPATH_FAULT=device-lost@submit:4 ;; 1) export WAVEPATH_FAULT=enospc@write:2 ;; esac
fi
exec "$wavepath" "\$@"
WRAPPER
chmod 755 "$faulty"
small=(-r 40 30 --checkpoint-every 0.001s)
fparts="$work/fault-parts"
faults=$(WAVEPATH="$faulty" sbatch --parsable --array=0-1 --output="$work/slurm-%A_%a.out" "$scripts/slurm/render-array.sh" 2 48 "$fparts" "$scene" "${small[@]}")
wait_gone "$faults" 120
check "a task whose device is lost says so and keeps its checkpoint, marked device lost" \
  $(grep -q "device lost: .*; finish with: " "$work/slurm-${faults}_0.out" && exr_attr "$fparts/checkpoints/part-0.exr" wavepath:status | grep -q "^device lost"; echo $?)
check "a task whose disk fills at a checkpoint says so, and the checkpoint before stays" \
  $(grep -q "part-1.exr: cannot write EXR: No space left on device" "$work/slurm-${faults}_1.out" &&
    [ "$(exr_attr "$fparts/checkpoints/part-1.exr" wavepath:status)" = checkpoint ]; echo $?)
reruns=$(WAVEPATH="$faulty" sbatch --parsable --array=0-1 --output="$work/slurm-%A_%a.out" "$scripts/slurm/render-array.sh" 2 48 "$fparts" "$scene" "${small[@]}")
fmerge=$(WAVEPATH="$wavepath" sbatch --parsable --dependency=afterok:"$reruns" --output="$work/slurm-fmerge.out" "$scripts/slurm/merge.sh" "$fparts" "$work/fmerged.png")
wait_gone "$fmerge" 120
check "resubmitted, the faulted tasks finish and merge: samples 0:48, complete" \
  $([ "$(exr_attr "$work/fmerged.exr" wavepath:samples)" = "0:48" ] && [ "$(exr_attr "$work/fmerged.exr" wavepath:status)" = complete ]; echo $?)
"$wavepath" render "$scene" -r 40 30 --spp 48 -q -o "$work/fsingle.png"
"$wavepath" compare --images "$work/fmerged.exr" "$work/fsingle.exr" >"$work/compare" 2>&1
check "the faulted tasks' merged image agrees with one process" $?
finish
