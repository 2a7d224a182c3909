#!/usr/bin/env bash
# Packs what a run on a GPU machine that lacks this machine's libraries
# needs into ./carry (git-ignored): bounce, the test programs named, the
# shared libraries they link that are not part of the C runtime, the Khronos
# validation layer (the tests run with it; xz-compressed) and, with
# --scenes DIR, the glTF scenes there. On the GPU machine:
#   tar -xJf carry/layer.tar.xz -C carry; export LD_LIBRARY_PATH=$PWD/carry/lib VK_ADD_LAYER_PATH=$PWD/carry/layer
#   carry/bin/bounce bench carry/scenes/sponza/Sponza.gltf ...
#   scripts/pack-for-gpu.sh [--scenes DIR] [TEST_PROGRAM ...]     (names from build/tests/)
set -euo pipefail
cd "$(dirname "$0")/.."
scenes=""
if [ "${1:-}" = --scenes ]; then
  scenes=$2
  shift 2
fi
rm -rf carry
mkdir -p carry/bin carry/lib carry/layer
cp build/bounce carry/bin/
for test in "$@"; do cp "build/tests/$test" carry/bin/; done
# Every library the programs link, but the C runtime and the Vulkan loader
# (the GPU machine has its own, or its loader comes in .gl/).
for program in carry/bin/*; do
  ldd "$program" | awk '$3 ~ /^\// { print $3 }'
done | sort -u | grep -vE '/(libc|libm|libgcc_s|libdl|libpthread|librt|libvulkan)\.so' | while read -r library; do
  cp -L "$library" carry/lib/
done
layer=/usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json
cp "$layer" carry/layer/
tar -cJf carry/layer.tar.xz -C /usr/lib/x86_64-linux-gnu libVkLayer_khronos_validation.so
[ -n "$scenes" ] && cp -r "$scenes" carry/scenes
du -sh carry
