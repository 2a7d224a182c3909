#!/usr/bin/env bash
# Installs everything Bounce needs to build, run and test, from Debian 12
# packages only. Idempotent: packages already present are left as they are,
# and apt is not even asked when nothing is missing.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  libvulkan-dev glslc spirv-tools spirv-headers
  mesa-vulkan-drivers vulkan-validationlayers vulkan-tools
  libglm-dev libstb-dev libopenexr-dev libcli11-dev libgtest-dev
  nlohmann-json3-dev libtinygltf-dev zlib1g-dev
  assimp-testmodels  # malformed glTF files the importer tests must refuse cleanly
  libglfw3-dev libimgui-dev  # bounce view's window and UI
  xvfb xauth  # an X server without a screen: the viewer's tests under lavapipe
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages already installed"
  exit 0
fi

if [ "$(id -u)" -ne 0 ]; then
  SUDO=sudo
  command -v sudo >/dev/null || { echo "install-deps: need root (or sudo) to install: ${missing[*]}" >&2; exit 1; }
else
  SUDO=
fi

echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
