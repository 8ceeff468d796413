#!/usr/bin/env bash
# The prepared run on a lent GPU machine (the `device` tool), from the
# repository root there, with what scripts/gpu-bundle.sh packed in
# .gpu.tar.xz and the Vulkan loader's glvnd packages in .gl (both carried;
# docs/benchmarks.md says how to make them): unpacks them, then runs the GPU
# tests (validation on, in four shards at once: one at a time they did not
# finish in 110 s) and scripts/bench-gpu.sh's STAGES (default core), each
# within its time (0 skips it), and prints the devices, the tests' verdicts
# and the benchmark's log.
# Usage: [STAGES=core|rest|all] scripts/gpu-run.sh OUT_DIR [TEST_SECONDS] [BENCH_SECONDS]   (default 90 360)
set -uo pipefail
out=${1:?usage: scripts/gpu-run.sh OUT_DIR [TEST_SECONDS] [BENCH_SECONDS]}
tests=${2:-90}
bench=${3:-360}
shards=4
mkdir -p "$out" && out=$(realpath "$out")
cd "$(dirname "$0")/.."
# The machine's driver is NVIDIA's, under /usr/local/nvidia; the loader's
# glvnd libraries it needs come from the carried Debian packages.
if [ -d /usr/local/nvidia ] && [ -d .gl ]; then
  for f in .gl/*.deb; do dpkg -x "$f" /; done
  ldconfig
fi
tar -xJf .gpu.tar.xz || { echo "no .gpu.tar.xz: run scripts/gpu-bundle.sh build .gpu here and carry it"; exit 2; }
export LD_LIBRARY_PATH=$PWD/.gpu/lib VK_ADD_LAYER_PATH=$PWD/.gpu/layers
icd=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
[ -f "$icd" ] && export VK_DRIVER_FILES=$icd
src=$(cat .gpu/source-dir)
if [ ! -e "$src" ]; then
  mkdir -p "$(dirname "$src")" && ln -s "$PWD" "$src"
elif [ "$(realpath "$src")" != "$PWD" ]; then
  echo "note: the GPU tests read their data from $src, another checkout"
fi
.gpu/bin/wavepath devices | tee "$out/devices.txt"
if [ "$tests" -gt 0 ]; then
  for ((i = 0; i < shards; ++i)); do
    (cd "$src" && GTEST_TOTAL_SHARDS=$shards GTEST_SHARD_INDEX=$i WAVEPATH_VALIDATION=1 \
      timeout "$tests" "$PWD/.gpu/bin/wavepath_gpu_tests" >"$out/gpu-tests-$i.txt" 2>&1; echo "exit $?" >>"$out/gpu-tests-$i.txt") &
  done
  wait
  echo "gpu tests, $shards shards within ${tests} s: $(cat "$out"/gpu-tests-*.txt | grep -c '^\[       OK') passed;" \
    "exits $(grep -h '^exit ' "$out"/gpu-tests-*.txt | cut -d' ' -f2 | xargs)"
  grep -h -E '^\[  FAILED|^\[  PASSED' "$out"/gpu-tests-*.txt | sort -u
fi
if [ "$bench" -gt 0 ]; then
  STAGES=${STAGES:-core} timeout "$bench" scripts/bench-gpu.sh .gpu/bin "$out/bench" >/dev/null 2>&1
  echo "bench-gpu.sh (${STAGES:-core}): exit $? (within ${bench} s)"
  grep -v '^\s*$' "$out/bench/log.txt"
fi
