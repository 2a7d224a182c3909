#!/usr/bin/env bash
# The specular branch against the reference path tracer: the numbers of
# docs/quality.md, "Indirect specular". Needs a GPU (hours on lavapipe).
#
#   scripts/studies/measure-specular.sh OUT_DIR [SCENES_DIR]
#
# For cornell, pillars, sun-room and (when SCENES_DIR has them) Sponza and
# the Breakfast Room at 640x360, default view, frame 32: the reference
# (REFERENCE_SPP samples, default 1024), then `bounce render` with the BVH
# bridge (defaults), without reuse, with uniform lobe sampling, with the
# bridge none, and with the diffuse branch alone (--gi diffuse): indirect
# specular mean / reference and relMSE, whole-frame relMSE and HDR-FLIP with
# and without the specular branch. Writes OUT_DIR/summary.md.
set -euo pipefail
out=${1:?usage: scripts/studies/measure-specular.sh OUT_DIR [SCENES_DIR]}
scenes_dir=${2:-}
# shellcheck source=scripts/measure-common.sh
source "$(dirname "$0")/../measure-common.sh"

echo "| scene | specular mean / ref: hybrid, no reuse, uniform, screen-only | specular relMSE: hybrid, no reuse, uniform, screen-only | frame relMSE: diffuse only, both | frame FLIP: diffuse only, both |" >> "$summary"
echo "|---|---|---|---|---|" >> "$summary"
for entry in "${entries[@]}"; do
  scene_reference "$entry"
  for mode in bvh noreuse uniform none diffuse; do
    flags=()
    [ "$mode" = noreuse ] && flags=(--gi.restir off)
    [ "$mode" = uniform ] && flags=(--gi.specular.sampling uniform)
    [ "$mode" = none ] && flags=(--scene-bridge none)
    [ "$mode" = diffuse ] && flags=(--gi diffuse)
    # shellcheck disable=SC2086
    "$bounce" render "$scene" "${size[@]}" $lighting "${flags[@]}" --gi-warmup 32 --frames 1 --hdr \
      --out "$dir/$mode" > "$dir/$mode.log"
  done
  sp() { echo "$dir/$1/frames/frame0000.indirect-specular.exr"; }
  fr() { echo "$dir/$1/frames/frame0000.exr"; }
  ref="$dir/ref.indirect-specular.exr"
  printf '| %s | %s, %s, %s, %s | %s, %s, %s, %s | %s, %s | %s, %s |\n' "$name" \
    "$(field "$ref" "$(sp bvh)" mean)" "$(field "$ref" "$(sp noreuse)" mean)" "$(field "$ref" "$(sp uniform)" mean)" \
    "$(field "$ref" "$(sp none)" mean)" \
    "$(field "$ref" "$(sp bvh)" relMSE)" "$(field "$ref" "$(sp noreuse)" relMSE)" "$(field "$ref" "$(sp uniform)" relMSE)" \
    "$(field "$ref" "$(sp none)" relMSE)" \
    "$(field "$dir/ref.exr" "$(fr diffuse)" relMSE)" "$(field "$dir/ref.exr" "$(fr bvh)" relMSE)" \
    "$(field "$dir/ref.exr" "$(fr diffuse)" FLIP)" "$(field "$dir/ref.exr" "$(fr bvh)" FLIP)" >> "$summary"
done
cat "$summary"
