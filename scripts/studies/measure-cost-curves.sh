#!/usr/bin/env bash
# The cost curves of docs/benchmarks.md: whole GI time and the library's
# device memory against resolution and triangle count, hybrid and
# screen-only. Needs a GPU.
#
#   scripts/studies/measure-cost-curves.sh OUT_DIR [SCENES_DIR]
#
# For every scene of measure-common.sh, `bounce bench` (--warmup 30 --frames
# 150, defaults) at 1280x720, 1920x1080, 2560x1440 and 3840x2160 with the
# scene bridges bvh (hybrid) and none (screen-only): OUT_DIR/NAME-WxH-BRIDGE.json.
# Then, here or anywhere:
#   scripts/plot_cost_curves.py resolution docs/images/cost-resolution.svg OUT_DIR/*.json
#   scripts/plot_cost_curves.py triangles docs/images/cost-triangles.svg OUT_DIR/*.json
set -euo pipefail
out=${1:?usage: scripts/studies/measure-cost-curves.sh OUT_DIR [SCENES_DIR]}
scenes_dir=${2:-}
# shellcheck source=scripts/measure-common.sh
source "$(dirname "$0")/../measure-common.sh"

for entry in "${entries[@]}"; do
  IFS='|' read -r name scene lighting <<< "$entry"
  for size in 1280x720 1920x1080 2560x1440 3840x2160; do
    for bridge in bvh none; do
      # shellcheck disable=SC2086
      "$bounce" bench "$scene" --width "${size%x*}" --height "${size#*x}" --warmup 30 --frames 150 --rays 0 \
        --copy-mb 0 $lighting --scene-bridge "$bridge" --json "$out/$name-$size-$bridge.json" > /dev/null
      echo "$name $size $bridge"
    done
  done
done
