#!/usr/bin/env bash
# Packs what a GPU machine without wavepath's build dependencies needs to run
# wavepath and its GPU tests: the two programs, the shared libraries they load
# (all but the C and C++ runtimes, which every Linux host has in a newer
# version), the Vulkan loader and the Khronos validation layer.
# Everything goes into one compressed archive, DEST.tar.xz (about 25 MiB),
# since the libraries (Embree's above all) are large.
# Usage: scripts/gpu-bundle.sh BUILD_DIR DEST
# On the GPU machine, from the repository root, scripts/gpu-run.sh unpacks
# it and runs the GPU tests and scripts/bench-gpu.sh (docs/benchmarks.md).
set -euo pipefail
build=$(realpath "$1")
dest=$2
rm -rf "$dest" "$dest.tar.xz" && mkdir -p "$dest/bin" "$dest/lib" "$dest/layers"
cp "$build/wavepath" "$build/tests/wavepath_gpu_tests" "$dest/bin/"
# The GPU tests read their data through the source path compiled into them.
sed -n 's/^CMAKE_HOME_DIRECTORY:INTERNAL=//p' "$build/CMakeCache.txt" >"$dest/source-dir"
skip='^(libc|libm|libdl|libpthread|librt|libstdc\+\+|libgcc_s|ld-linux-x86-64)\.so'
for program in "$dest"/bin/*; do
  ldd "$program" | awk '/=> \// { print $3 }'
done | sort -u | while read -r lib; do
  name=$(basename "$lib")
  [[ $name =~ $skip ]] || cp -L "$lib" "$dest/lib/$name"
done
layer=$(ls /usr/lib/x86_64-linux-gnu/libVkLayer_khronos_validation.so 2>/dev/null || true)
if [ -n "$layer" ]; then
  cp "$layer" "$dest/layers/"
  sed 's|"library_path": *"[^"]*"|"library_path": "./libVkLayer_khronos_validation.so"|' \
    /usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json >"$dest/layers/VkLayer_khronos_validation.json"
fi
strip "$dest"/bin/* "$dest"/lib/*.so* "$dest"/layers/*.so 2>/dev/null || true
tar -cJf "$dest.tar.xz" "$dest"
rm -rf "$dest"
du -sh "$dest.tar.xz"
