#!/usr/bin/env bash
# The faults a render farm meets, injected through WAVEPATH_FAULT
# (src/util/fault.h; docs/partial-renders.md, "Faults"): a device lost in
# the middle of a render keeps the samples of the passes it finished, exits
# 75 and prints the command that finishes the render, which gives the
# uninterrupted image; among several devices the others take over the lost
# one's samples; out of device memory the render goes on in smaller tiles,
# or refuses in one line where one row does not fit; a full disk (injected,
# and a real one where a tmpfs can be mounted) leaves the checkpoint written
# before intact and exits 3.
# Usage: faults_cli.sh WAVEPATH TEST_DATA_DIR
set -u
wavepath=$1
data=$2
source "$(dirname "$0")/testlib.sh"
scene="$data/features/materials.json"
r=(-r 40 30 --spp 48 -q)
no_temporary_files() { ! ls "$work"/*.tmp* >/dev/null 2>&1; }

"$wavepath" render "$scene" "${r[@]}" -o "$work/whole.png"

# A device lost at the 4th submission, checkpointing after every pass.
WAVEPATH_FAULT=device-lost@submit:4 "$wavepath" render "$scene" "${r[@]}" -o "$work/lost.png" \
  --checkpoint "$work/ck.exr" --checkpoint-every 0.001s >"$work/out" 2>"$work/err"
rc=$?
kept=$(exr_attr "$work/lost.exr" wavepath:samples)
check "device lost: exit 75 (got $rc), one line naming the device and the samples kept ($kept)" \
  $([ $rc -eq 75 ] && [ "$(wc -l <"$work/err")" -eq 1 ] && grep -qE "^wavepath: device lost: .+: kept samples $kept \(of 0:48\)" "$work/err"; echo $?)
check "device lost: the image, the EXR and the checkpoint hold samples 0:N, N < 48, marked device lost" \
  $(echo "$kept" | grep -qE '^0:([1-9]|[1-3][0-9]|4[0-7])$' && [ -s "$work/lost.png" ] &&
    [ "$(exr_attr "$work/ck.exr" wavepath:samples)" = "$kept" ] && exr_attr "$work/ck.exr" wavepath:status | grep -q "^device lost: ."; echo $?)
cp "$work/lost.exr" "$work/part.exr"
# The parts the lost render kept and the rest merge exactly (no overlap, no gap).
"$wavepath" render "$scene" "${r[@]}" --samples "${kept#0:}:48" -o "$work/rest.png"
"$wavepath" merge "$work/part.exr" "$work/rest.exr" -q -o "$work/merged.png"
check "device lost: its part and samples ${kept#0:}:48 merge into samples 0:48, complete" \
  $([ $? -eq 0 ] && [ "$(exr_attr "$work/merged.exr" wavepath:samples)" = "0:48" ] && [ "$(exr_attr "$work/merged.exr" wavepath:status)" = complete ]; echo $?)
# The printed command finishes the render.
finish_with=$(sed -n 's/.*; finish with: wavepath //p' "$work/err")
eval "\"\$wavepath\" $finish_with -q" >"$work/out" 2>&1
check "device lost: the printed command ($finish_with) finishes it: samples 0:48, complete" \
  $([ $? -eq 0 ] && [ "$(exr_attr "$work/lost.exr" wavepath:samples)" = "0:48" ] && [ "$(exr_attr "$work/lost.exr" wavepath:status)" = complete ]; echo $?)
"$wavepath" compare --images "$work/lost.exr" "$work/whole.exr" >"$work/out" 2>&1
check "device lost, finished: agrees with the uninterrupted render" $?

# Several devices: the one lost (the 2nd submission of the process, on
# either) leaves its samples to the others; the render completes.
for devices in 0,0 0,cpu; do
  WAVEPATH_FAULT=device-lost@submit:2 "$wavepath" render "$scene" -r 40 30 --spp 48 --devices $devices -o "$work/devices.png" \
    >"$work/out" 2>"$work/err"
  check "--devices $devices, one lost: exit 0, samples 0:48 complete, the summary and a line name the lost device" \
    $([ $? -eq 0 ] && [ "$(exr_attr "$work/devices.exr" wavepath:samples)" = "0:48" ] &&
      [ "$(exr_attr "$work/devices.exr" wavepath:status)" = complete ] && grep -q "(lost)" "$work/out" &&
      [ "$(wc -l <"$work/err")" -eq 1 ] && grep -q "device lost: .* during samples .*the other devices rendered the rest" "$work/err"; echo $?)
  "$wavepath" compare --images "$work/devices.exr" "$work/whole.exr" >"$work/out" 2>&1
  check "--devices $devices, one lost: agrees with the uninterrupted render" $?
done

# Out of device memory: a 64x32 image's buffers take about 450 KB; in 200 KB
# the render goes on in smaller tiles. One row of 4096 pixels does not fit
# in 600 KB: refused, naming what it needs and what the device holds.
WAVEPATH_FAULT=oom@bytes:200000 "$wavepath" render "$scene" -r 64 32 --spp 16 -q -o "$work/oom.png" 2>"$work/err"
check "out of device memory: exit 0, one line saying the tiles shrank" \
  $([ $? -eq 0 ] && [ "$(wc -l <"$work/err")" -eq 1 ] && grep -q "out of device memory for tiles of 2048 pixels .*; rendering in tiles of" "$work/err"; echo $?)
"$wavepath" render "$scene" -r 64 32 --spp 16 -q -o "$work/oom-whole.png"
"$wavepath" compare --images "$work/oom.exr" "$work/oom-whole.exr" >"$work/out" 2>&1
check "out of device memory: the image in smaller tiles agrees with the untiled one" $?
WAVEPATH_FAULT=oom@bytes:600000 "$wavepath" render "$scene" -r 4096 2 --spp 1 -q -o "$work/row.png" 2>"$work/err"
check "out of device memory for one row: exit 3, one line naming the need and the limit, no image" \
  $([ $? -eq 3 ] && [ "$(wc -l <"$work/err")" -eq 1 ] && grep -q "even tiles of one row (4096 pixels) need .* more than .*holds" "$work/err" &&
    [ ! -e "$work/row.png" ]; echo $?)

# A full disk at the 2nd file written: the first checkpoint was written,
# the second is not; the first stays, the render stops (exit 3) naming the
# file and the error, and writes no image. Resumed, it finishes.
WAVEPATH_FAULT=enospc@write:2 "$wavepath" render "$scene" "${r[@]}" -o "$work/full.png" --checkpoint "$work/ck2.exr" \
  --checkpoint-every 0.001s 2>"$work/err"
rc=$?
ck=$(exr_attr "$work/ck2.exr" wavepath:samples)
check "full disk at a checkpoint: exit 3 (got $rc), one line naming the file and the error" \
  $([ $rc -eq 3 ] && [ "$(wc -l <"$work/err")" -eq 1 ] && grep -q "ck2.exr: cannot write EXR: No space left on device (the checkpoint there, of samples $ck, is intact)" "$work/err"; echo $?)
check "full disk at a checkpoint: the one before holds samples $ck, no image, no temporary file" \
  $(echo "$ck" | grep -qE '^0:[0-9]+$' && [ "$(exr_attr "$work/ck2.exr" wavepath:status)" = checkpoint ] && [ ! -e "$work/full.png" ] &&
    [ ! -e "$work/full.exr" ] && no_temporary_files; echo $?)
"$wavepath" render "$scene" "${r[@]}" -o "$work/full.png" --checkpoint "$work/ck2.exr" --resume "$work/ck2.exr"
check "full disk at a checkpoint: resumed, it finishes" \
  $([ $? -eq 0 ] && [ "$(exr_attr "$work/full.exr" wavepath:samples)" = "0:48" ]; echo $?)
# The image after its EXR: both or neither.
WAVEPATH_FAULT=enospc@write:2 "$wavepath" render "$scene" "${r[@]}" -o "$work/out2.png" 2>"$work/err"
check "full disk at the image: exit 3, naming it, and neither the image nor its EXR left" \
  $([ $? -eq 3 ] && grep -q "out2.png: cannot write image: No space left on device" "$work/err" && [ ! -e "$work/out2.png" ] &&
    [ ! -e "$work/out2.exr" ] && no_temporary_files; echo $?)

# A real full disk, where a 12 KiB tmpfs can be mounted (root with the right
# to mount): the EXR (20 KB) does not fit; the same line, the same status.
mkdir "$work/full"
if mount -t tmpfs -o size=12k tmpfs "$work/full" 2>/dev/null; then
  "$wavepath" render "$scene" "${r[@]}" -o "$work/full/x.png" 2>"$work/err"
  rc=$?
  left=$(ls -A "$work/full")
  umount "$work/full"
  check "a real full disk: exit 3 (got $rc), one line naming the file and the error, no file left" \
    $([ $rc -eq 3 ] && [ "$(wc -l <"$work/err")" -eq 1 ] && grep -q "full/x.exr: cannot write EXR: .*No space left on device" "$work/err" &&
      [ -z "$left" ]; echo $?)
else
  pass "a real full disk (skipped: no tmpfs can be mounted here)"
fi

bad "a WAVEPATH_FAULT that names no fault" "WAVEPATH_FAULT: \"oom@submit:1\" is not a fault" -- \
  env WAVEPATH_FAULT=oom@submit:1 "$wavepath" render "$scene" "${r[@]}" -o "$work/x.png"
finish
