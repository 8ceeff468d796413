#!/usr/bin/env bash
# Fuzzes wavepath's input loaders (darts JSON scenes and test files, OBJ meshes, image files,
# partial renders, glTF models, CS184 COLLADA scenes, NanoVDB density grids)
# with libFuzzer, under AddressSanitizer and UndefinedBehaviorSanitizer.
#
#   scripts/fuzz.sh [SECONDS_PER_TARGET] [BUILD_DIR]
#
# Needs Clang and its fuzzer runtime (Debian: clang, libclang-rt-14-dev).
# Seeds each target with the repository's scenes, meshes, images and bad-input
# cases; crashes land in BUILD_DIR/fuzz-out/KIND/ (libFuzzer's crash-*,
# timeout-*, oom-* files). Copy each one, once fixed, into
# tests/fuzz/findings/KIND/ as loads-NAME or refused-NAME: the test suite
# replays them (Loaders.FuzzFindingsAreHandledAsRecorded).
set -euo pipefail
seconds=${1:-60}
build=${2:-build-fuzz}
src=$(cd "$(dirname "$0")/.." && pwd)

CC=clang CXX=clang++ cmake -S "$src" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DWAVEPATH_FUZZ=ON \
  -DCMAKE_CXX_FLAGS="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer -fsanitize=fuzzer-no-link" >/dev/null
cmake --build "$build" -j"$(nproc)" --target fuzz_scene fuzz_obj fuzz_image fuzz_partial fuzz_gltf fuzz_collada fuzz_nvdb wavepath-volume

seeds() {  # the seed corpus of one kind, in a folder of its own
  local kind=$1 dir=$build/fuzz-seeds/$1
  rm -rf "$dir" && mkdir -p "$dir"
  case $kind in
    scene)
      cp "$src"/scenes/*.json "$src"/tests/data/*.json "$src"/tests/data/darts/*.json "$dir"/
      for f in "$src"/tests/data/features/*.json; do cp "$f" "$dir/feature-$(basename "$f")"; done
      ;;
    obj) cp "$src"/tests/data/*.obj "$dir"/ && find "$src/scenes/assets" -name '*.obj' -size -64k -exec cp {} "$dir"/ \; ;;
    image)  # the first byte names the file: 0 input.png (stb_image, by content), 1 input.exr, 2 input.tga
      for f in "$src"/tests/data/*.png "$src"/scenes/assets/*.png "$src"/scenes/assets/*.hdr; do
        [ -f "$f" ] && { printf '\0'; cat "$f"; } >"$dir/$(basename "$f")"
      done
      for f in "$src"/tests/data/*.exr; do [ -f "$f" ] && { printf '\1'; cat "$f"; } >"$dir/$(basename "$f")"; done
      ;;
    partial) ;;  # the partial files under tests/fuzz/findings/partial/ (below)
    gltf)  # the first byte names the file: 0 input.gltf, 1 input.glb
      for f in "$src"/tests/data/gltf/*.gltf "$src"/tests/data/gltf/external/*.gltf; do { printf '\0'; cat "$f"; } >"$dir/$(basename "$f")"; done
      for f in "$src"/tests/data/gltf/*.glb; do { printf '\1'; cat "$f"; } >"$dir/$(basename "$f")"; done
      ;;
    collada) cp "$src"/tests/data/collada/*.dae "$dir"/ ;;
    nvdb)
      cp "$src"/scenes/*.nvdb "$dir"/
      "$build/wavepath-volume" ramp "$dir/ramp.nvdb" 12 0.5 0.1
      "$build/wavepath-volume" plume "$dir/plume-small.nvdb" 16
      ;;
  esac
  if [ -d "$src/tests/fuzz/findings/$kind" ]; then cp "$src/tests/fuzz/findings/$kind"/* "$dir"/ 2>/dev/null || true; fi
  echo "$dir"
}

# Leaks inside third-party decoders that wavepath cannot free (see the file).
export LSAN_OPTIONS="suppressions=$src/tests/fuzz/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
status=0
for kind in scene obj image partial gltf collada nvdb; do
  out=$build/fuzz-out/$kind corpus=$build/fuzz-corpus/$kind
  mkdir -p "$out" "$corpus"
  echo "== fuzz_$kind for ${seconds}s"
  # -rss_limit_mb: an input that makes a loader take gigabytes is a finding too.
  if ! "$build/tests/fuzz_$kind" "$corpus" "$(seeds "$kind")" -max_total_time="$seconds" -timeout=10 \
      -rss_limit_mb=2048 -artifact_prefix="$out/" -print_final_stats=1 2>"$out/log.txt"; then
    status=1
    echo "   finding(s) in $out:"; ls "$out" | grep -v log.txt | sed 's/^/     /'
  fi
  tail -n 12 "$out/log.txt" | grep -E "stat::number_of_executed_units|cov:|SUMMARY" || true
done
exit $status
