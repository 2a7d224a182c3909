#!/usr/bin/env bash
# Screen-only against hybrid (the renderer's BVH scene bridge) against the
# reference path tracer: the numbers of docs/quality.md, "Seeing beyond the
# screen". Needs a GPU (hours on lavapipe).
#
#   scripts/studies/measure-hybrid.sh OUT_DIR [SCENES_DIR]
#
# For cornell, pillars, sun-room and (when SCENES_DIR has them) Sponza and
# the Breakfast Room at 640x360, at the default view and at frame 32 of the
# orbit path: the reference (REFERENCE_SPP samples, default 1024), then
# `bounce render` after 32 frames with --scene-bridge none and bvh (and bvh
# without reuse, and bvh with the unbiased option gi.diffuse.reuse_visibility),
# each compared: indirect-diffuse mean / reference and relMSE, whole-frame
# relMSE and HDR-FLIP. Writes OUT_DIR/summary.md.
set -euo pipefail
out=${1:?usage: scripts/studies/measure-hybrid.sh OUT_DIR [SCENES_DIR]}
scenes_dir=${2:-}
# shellcheck source=scripts/measure-common.sh
source "$(dirname "$0")/../measure-common.sh"

echo "| scene | view | indirect mean / ref: none, hybrid, unbiased | indirect relMSE: none, hybrid, hybrid no reuse, unbiased | frame relMSE: none, hybrid | frame FLIP: none, hybrid |" >> "$summary"
echo "|---|---|---|---|---|---|" >> "$summary"
for entry in "${entries[@]}"; do
  IFS='|' read -r name scene lighting <<< "$entry"
  for view in front orbit32; do
    dir="$out/$name-$view"
    mkdir -p "$dir"
    camera=()
    frame=0000
    [ "$view" = orbit32 ] && camera=(--camera orbit) && frame=0032
    # shellcheck disable=SC2086
    "$bounce" reference "$scene" "${size[@]}" $lighting "${camera[@]}" ${camera:+--frame 32} --spp "$spp" --seed 7 \
      --out "$dir/ref.exr" > "$dir/ref.log"
    frames=1
    [ "$view" = orbit32 ] && frames=33
    for mode in none bvh bvh-noreuse bvh-unbiased; do
      flags=(--scene-bridge "${mode%%-*}")
      [ "$mode" = bvh-noreuse ] && flags+=(--gi.restir off)
      [ "$mode" = bvh-unbiased ] && flags+=(--gi.diffuse.reuse_visibility on)
      # shellcheck disable=SC2086
      "$bounce" render "$scene" "${size[@]}" $lighting "${camera[@]}" "${flags[@]}" --gi-warmup 32 --frames $frames \
        --hdr --out "$dir/$mode" > "$dir/$mode.log"
    done
    id() { echo "$dir/$1/frames/frame$frame.indirect-diffuse.exr"; }
    fr() { echo "$dir/$1/frames/frame$frame.exr"; }
    printf '| %s | %s | %s, %s, %s | %s, %s, %s, %s | %s, %s | %s, %s |\n' "$name" "$view" \
      "$(field "$dir/ref.indirect-diffuse.exr" "$(id none)" mean)" "$(field "$dir/ref.indirect-diffuse.exr" "$(id bvh)" mean)" \
      "$(field "$dir/ref.indirect-diffuse.exr" "$(id bvh-unbiased)" mean)" \
      "$(field "$dir/ref.indirect-diffuse.exr" "$(id none)" relMSE)" "$(field "$dir/ref.indirect-diffuse.exr" "$(id bvh)" relMSE)" \
      "$(field "$dir/ref.indirect-diffuse.exr" "$(id bvh-noreuse)" relMSE)" "$(field "$dir/ref.indirect-diffuse.exr" "$(id bvh-unbiased)" relMSE)" \
      "$(field "$dir/ref.exr" "$(fr none)" relMSE)" "$(field "$dir/ref.exr" "$(fr bvh)" relMSE)" \
      "$(field "$dir/ref.exr" "$(fr none)" FLIP)" "$(field "$dir/ref.exr" "$(fr bvh)" FLIP)" >> "$summary"
  done
done
cat "$summary"
