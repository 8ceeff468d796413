#!/usr/bin/env bash
# Installs the Debian 12 packages wavepath needs to build, render and test.
# Uses sudo when not run as root. See docs/dependencies.md for why each.
set -euo pipefail
packages=(
  cmake g++ make pkg-config
  libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers glslang-tools spirv-tools
  libglm-dev nlohmann-json3-dev libcli11-dev libtinyobjloader-dev libtinygltf-dev libpugixml-dev libstb-dev libopenexr-dev libtbb-dev libnanovdb-dev
  libembree-dev python3-numpy python3-matplotlib
  pybind11-dev python3-pybind11 python3-dev python3-pytest
  libglfw3-dev xvfb xauth xdotool imagemagick
  libgtest-dev chromium
  slurm-wlm munge
)
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "installing: ${missing[*]}"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
