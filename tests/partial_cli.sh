#!/usr/bin/env bash
# Partial renders as a user meets them: --samples parts merged with
# `wavepath merge` agree with one render; merge refuses gaps, overlaps and
# parts of other renders (exit 2, one line); Ctrl-C stops a render at the end
# of a pass and leaves the image so far, marked partial, and the checkpoint,
# which --resume continues; a second Ctrl-C aborts at once; --time stops when
# the budget is spent.
# Usage: partial_cli.sh WAVEPATH TEST_DATA_DIR
set -u
wavepath=$1
data=$2
source "$(dirname "$0")/testlib.sh"
scene="$data/features/materials.json"
r=(-r 40 30 --spp 48 -q)


"$wavepath" render "$scene" "${r[@]}" -o "$work/whole.png"
"$wavepath" render "$scene" "${r[@]}" --samples 0:16 -o "$work/a.png"
"$wavepath" render "$scene" "${r[@]}" --samples 16:40 --cpu -o "$work/b.png"
"$wavepath" render "$scene" "${r[@]}" --samples 40:48 -o "$work/c.png"
check "a part's header names its samples" $([ "$(exr_attr "$work/b.exr" wavepath:samples)" = "16:40" ]; echo $?)
"$wavepath" merge "$work/c.exr" "$work/a.exr" "$work/b.exr" -o "$work/merged.png" >"$work/out" 2>&1
check "merge of GPU and CPU parts: exit 0" $?
check "the merged file holds samples 0:48, complete" \
  $([ "$(exr_attr "$work/merged.exr" wavepath:samples)" = "0:48" ] && [ "$(exr_attr "$work/merged.exr" wavepath:status)" = complete ]; echo $?)
"$wavepath" compare --images "$work/merged.exr" "$work/whole.exr" >"$work/out" 2>&1
check "the merged image agrees with one render (compare exit 0)" $?

# Tiles (--tile-pixels far below lavapipe's limit, so that this small render
# takes several): a tiled part merges with an untiled one into what one
# render gives; a tiled render stopped by its time budget and resumed, tiled,
# is complete and agrees with one uninterrupted render.
"$wavepath" render "$scene" "${r[@]}" --samples 0:16 --tile-pixels 333 -o "$work/tile-a.png"
"$wavepath" render "$scene" "${r[@]}" --samples 16:48 -o "$work/tile-b.png"
"$wavepath" merge "$work/tile-a.exr" "$work/tile-b.exr" -o "$work/tile-merged.png" -q
check "a part rendered in tiles merges with an untiled one" $?
"$wavepath" compare --images "$work/tile-merged.exr" "$work/whole.exr" >"$work/out" 2>&1
check "the merged tiled and untiled parts agree with one render" $?
"$wavepath" render "$scene" -r 64 64 --spp 100000 --tile-pixels 1000 --time 2s -q -o "$work/tile-stop.png" --checkpoint "$work/tile-ck.exr"
stopped=$(exr_attr "$work/tile-stop.exr" wavepath:samples)
check "a tiled render stops at its budget with samples 0:N (got $stopped)" $(echo "$stopped" | grep -qE '^0:[0-9]+$'; echo $?)
"$wavepath" render "$scene" -r 64 64 --spp 100000 --tile-pixels 1000 --time 2s -q -o "$work/tile-res.png" --resume "$work/tile-stop.exr"
resumed=$(exr_attr "$work/tile-res.exr" wavepath:samples)
check "resumed in tiles: the samples grew ($stopped to $resumed)" $([ "${resumed#0:}" -gt "${stopped#0:}" ]; echo $?)
"$wavepath" render "$scene" -r 64 64 --spp 100000 --samples "${resumed:-0:1}" -q -o "$work/tile-whole.png"
"$wavepath" compare --images "$work/tile-res.exr" "$work/tile-whole.exr" >"$work/out" 2>&1
check "resumed in tiles: agrees with one uninterrupted render of samples $resumed" $?

# Merge memory: parts are read and added a block of rows at a time, so the
# merge's peak resident memory stays below the sums of the image it writes
# (2048x1024: 151 MB in double); a merge holding the image whole needs twice that.
for i in 0 1; do
  "$wavepath" render "$data/features/materials.json" -r 2048 1024 --spp 2 --samples $i:$((i + 1)) --cpu -q -o "$work/big$i.png"
done
peak=$(python3 -c 'import resource, subprocess, sys
subprocess.run(sys.argv[1:], check=True)
print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss // 1024)' "$wavepath" merge "$work/big0.exr" "$work/big1.exr" -q -o "$work/big.png")
check "a 2048x1024 merge peaks at ${peak} MiB, under the image's 144 MiB of sums" $([ -n "$peak" ] && [ "$peak" -lt 144 ] && [ -s "$work/big.png" ]; echo $?)
rm -f "$work"/big*.exr

# The photon mapper: parts whose photon maps were traced by the kernels
# (--photon-pass kernels) and by the CPU reference merge into what one
# render gives; the pass is reported.
pm=(-r 32 24 --spp 16 -q)
"$wavepath" render "$data/features/photons.json" "${pm[@]}" --photon-pass kernels --stage-times -o "$work/pm-whole.png" >"$work/out" 2>&1
check "--photon-pass kernels: the photon map's pass is reported" $(grep -q "^photon map: [1-9][0-9]* records" "$work/out"; echo $?)
"$wavepath" render "$data/features/photons.json" "${pm[@]}" --samples 0:8 --photon-pass kernels -o "$work/pm-a.png"
"$wavepath" render "$data/features/photons.json" "${pm[@]}" --samples 8:16 --cpu -o "$work/pm-b.png"
"$wavepath" merge "$work/pm-a.exr" "$work/pm-b.exr" -o "$work/pm-merged.png" -q
check "photon-mapped parts of the kernels' and the host's maps merge" $?
"$wavepath" compare --images "$work/pm-merged.exr" "$work/pm-whole.exr" >"$work/out" 2>&1
check "the merged photon-mapped image agrees with one render" $?

# Several renderers in one process: lavapipe twice, lavapipe and the CPU
# reference; chunks of samples go to whichever is free.
for devices in 0,0 0,cpu; do
  "$wavepath" render "$scene" "${r[@]}" --devices $devices -o "$work/devices.png" >"$work/out" 2>&1
  check "--devices $devices: exit 0, samples 0:48 complete" \
    $([ $? -eq 0 ] && [ "$(exr_attr "$work/devices.exr" wavepath:samples)" = "0:48" ] && [ "$(exr_attr "$work/devices.exr" wavepath:status)" = complete ]; echo $?)
  "$wavepath" compare --images "$work/devices.exr" "$work/whole.exr" >"$work/out" 2>&1
  check "--devices $devices: agrees with one device" $?
done

"$wavepath" render "$scene" "${r[@]}" --samples 16:40 --seed 7 -o "$work/seed7.png"
"$wavepath" render "$data/quad-light.json" "${r[@]}" --samples 16:40 -o "$work/other.png"
bad "a gap" "leave out samples 16:40" -- "$wavepath" merge "$work/a.exr" "$work/c.exr" -o "$work/x.png"
bad "an overlap" "overlaps" -- "$wavepath" merge "$work/a.exr" "$work/b.exr" "$work/b.exr" "$work/c.exr" -o "$work/x.png"
bad "other settings" "seed 7 vs 0" -- "$wavepath" merge "$work/a.exr" "$work/seed7.exr" "$work/c.exr" -o "$work/x.png"
bad "another scene" "another scene" -- "$wavepath" merge "$work/a.exr" "$work/other.exr" "$work/c.exr" -o "$work/x.png"
bad "a range past the render" "goes past the render's 48 samples" -- "$wavepath" render "$scene" "${r[@]}" --samples 40:64 -o "$work/x.png"
bad "a duration that is none" "is not a duration" -- "$wavepath" render "$scene" "${r[@]}" --time soon -o "$work/x.png"
bad "a checkpoint that is no EXR" "must be an .exr file" -- "$wavepath" render "$scene" "${r[@]}" --checkpoint "$work/ck.png" -o "$work/x.png"
bad "an unknown AOV layer" "unknown output layer \"depht\"" -- "$wavepath" render "$scene" "${r[@]}" --aov depht -o "$work/x.png"
bad "a range backwards" "not a sample range" -- "$wavepath" render "$scene" "${r[@]}" --samples 9:3 -o "$work/x.png"
bad "--cpu with --devices" "--devices" -- "$wavepath" render "$scene" "${r[@]}" --cpu --devices 0,cpu -o "$work/x.png"
bad "merging a plain render" "lacks the exact sums" -- "$wavepath" merge "$work/whole.exr" "$work/a.exr" -o "$work/x.png"
bad "merging a missing file" "missing.exr" -- "$wavepath" merge "$work/a.exr" "$work/missing.exr" -o "$work/x.png"
bad "resuming a missing checkpoint" "no-such.exr" -- "$wavepath" render "$scene" "${r[@]}" --resume "$work/no-such.exr" -o "$work/x.png"
check "no output of a refused command" $([ ! -e "$work/x.png" ] && [ ! -e "$work/x.exr" ]; echo $?)
"$wavepath" merge "$work/a.exr" "$work/c.exr" --allow-gaps -o "$work/gappy.png" >"$work/out" 2>&1
check "--allow-gaps merges and records what is missing" \
  $([ $? -eq 0 ] && [ "$(exr_attr "$work/gappy.exr" wavepath:status)" = "partial: samples 16:40 missing" ]; echo $?)

# AOV layers on the command line: written to the EXR, merged, compared.
"$wavepath" render "$scene" "${r[@]}" --samples 0:24 --aov albedo,normal,depth -o "$work/aov-a.png"
"$wavepath" render "$scene" "${r[@]}" --samples 24:48 --aov depth,albedo,normal --cpu -o "$work/aov-b.png"
"$wavepath" merge "$work/aov-a.exr" "$work/aov-b.exr" -o "$work/aov.png" -q
check "AOV parts (GPU and CPU) merge" $?
"$wavepath" render "$scene" "${r[@]}" --aov albedo,normal,depth --cpu --seed 3 -o "$work/aov-c.png"
for layer in albedo normal depth; do
  "$wavepath" compare --images "$work/aov.exr" "$work/aov-c.exr" --layer $layer >"$work/out" 2>&1
  check "compare --layer $layer: the merged layer agrees with another render's" $?
done
bad "compare --layer of a layer not rendered" "has no \"albedo\" layer" -- \
  "$wavepath" compare --images "$work/whole.exr" "$work/aov-c.exr" --layer albedo

# Ctrl-C: the render stops at the end of a pass, writes what it has, marked
# partial, and exits with the shell's status for SIGINT.
long=(-r 64 64 --spp 1000000)
"$wavepath" render "$scene" "${long[@]}" -o "$work/int.png" --checkpoint "$work/ck.exr" >"$work/out" 2>"$work/err" &
pid=$!
sleep 4
kill -INT $pid
t0=$(date +%s%N)
wait $pid
rc=$?
took=$((($(date +%s%N) - t0) / 1000000))
check "SIGINT: exit 130" $([ $rc -eq 130 ]; echo $?)
check "SIGINT: stopped within 2 s (took $took ms)" $([ $took -lt 2000 ]; echo $?)
check "SIGINT: the message says interrupted" $(grep -q "interrupted by SIGINT" "$work/err"; echo $?)
check "SIGINT: PNG, EXR and checkpoint written" $([ -s "$work/int.png" ] && [ -s "$work/int.exr" ] && [ -s "$work/ck.exr" ]; echo $?)
check "SIGINT: the EXR header says interrupted" $([ "$(exr_attr "$work/int.exr" wavepath:status)" = "interrupted by SIGINT" ]; echo $?)
reached=$(exr_attr "$work/ck.exr" wavepath:samples)
check "SIGINT: the checkpoint holds samples 0:N (got $reached)" $(echo "$reached" | grep -qE '^0:[0-9]+$'; echo $?)

# --resume continues the checkpoint; with --time it stops again, a success.
"$wavepath" render "$scene" "${long[@]}" -o "$work/res.png" --resume "$work/ck.exr" --checkpoint "$work/ck.exr" --time 3s \
  >"$work/out" 2>"$work/err"
rc=$?
again=$(exr_attr "$work/res.exr" wavepath:samples)
check "--time: exit 0, and the samples reached grew (${reached} to ${again})" \
  $([ $rc -eq 0 ] && [ "${again#0:}" -gt "${reached#0:}" ]; echo $?)
check "--time: the header says the budget was spent" $(exr_attr "$work/res.exr" wavepath:status | grep -q "time budget of 3s spent"; echo $?)
bad "resuming another render's checkpoint" "seed 0 vs 5" -- \
  "$wavepath" render "$scene" "${long[@]}" --seed 5 -o "$work/x.png" --resume "$work/ck.exr"

# Interrupted on two devices, the parts done may leave gaps; --resume
# renders just those.
"$wavepath" render "$scene" -r 64 64 --spp 4000 --devices 0,cpu -o "$work/dint.png" --checkpoint "$work/dck.exr" \
  >"$work/out" 2>"$work/err" &
pid=$!
sleep 4
kill -INT $pid
wait $pid
rc=$?
check "--devices, SIGINT: exit 130, marked interrupted" $([ $rc -eq 130 ] && [ "$(exr_attr "$work/dint.exr" wavepath:status)" = "interrupted by SIGINT" ]; echo $?)
"$wavepath" render "$scene" -r 64 64 --spp 4000 --devices 0,cpu -o "$work/dres.png" --resume "$work/dck.exr" >"$work/out" 2>"$work/err"
check "--devices, resumed: exit 0, samples 0:4000 complete (from $(exr_attr "$work/dck.exr" wavepath:samples))" \
  $([ $? -eq 0 ] && [ "$(exr_attr "$work/dres.exr" wavepath:samples)" = "0:4000" ] && [ "$(exr_attr "$work/dres.exr" wavepath:status)" = complete ]; echo $?)
"$wavepath" render "$scene" -r 64 64 --spp 4000 -q -o "$work/dwhole.png"
"$wavepath" compare --images "$work/dres.exr" "$work/dwhole.exr" >"$work/out" 2>&1
check "--devices, resumed: agrees with one uninterrupted render" $?

# A second Ctrl-C aborts at once: nothing is written. Passes of a
# megapixel take over a second here; the signals come 20 ms apart, just after
# the first pass (its checkpoint appears), so both land inside the second.
"$wavepath" render "$scene" -r 1024 1024 --spp 1000000 -q -o "$work/abort.png" --checkpoint "$work/ck2.exr" \
  --checkpoint-every 0.001s >"$work/out" 2>"$work/err" &
pid=$!
for _ in $(seq 1500); do [ -e "$work/ck2.exr" ] && break; sleep 0.02; done
kill -INT $pid
sleep 0.02
kill -INT $pid
wait $pid
rc=$?
check "a second SIGINT: exit 130, no image written" $([ $rc -eq 130 ] && [ ! -e "$work/abort.png" ] && [ ! -e "$work/abort.exr" ]; echo $?)
finish
