#!/usr/bin/env bash
# The denoiser against what it is given (issue 14's error bar): for every
# scene of measure-common.sh (SCENES_DIR may be ''), the reference once,
# then `bounce render` (640x360, frame WARMUP: 32 unless the variable says
# otherwise; default view) with the default settings (the denoiser on,
# stages dumped) and with --gi.denoise.enabled off (the branches' own
# temporal filters). Per signal: relMSE against the reference of the
# undenoised signal (the branch's resolve, which the denoiser takes), of
# the filters' output and of the denoised output, and the ratio denoised /
# undenoised (the bar: at most 1/3). Needs a GPU.
#
#   scripts/studies/measure-denoiser.sh OUT_DIR SCENES_DIR
#
# Writes OUT_DIR/summary.md.
set -euo pipefail
out=${1:?usage: scripts/studies/measure-denoiser.sh OUT_DIR SCENES_DIR}
scenes_dir=${2?usage: scripts/studies/measure-denoiser.sh OUT_DIR SCENES_DIR}
# shellcheck source=scripts/measure-common.sh
source "$(dirname "$0")/../measure-common.sh"

frame=$(printf 'frame%04d' 0)
{
  echo "| scene | diffuse relMSE: undenoised, filters, denoised | ratio | specular relMSE: undenoised, filters, denoised | ratio |"
  echo "|---|---|---|---|---|"
} >> "$summary"
for entry in "${entries[@]}"; do
  scene_reference "$entry"
  for variant in denoised filters; do
    flags=(--dump-stages)
    [ "$variant" = filters ] && flags=(--gi.denoise.enabled off)
    # shellcheck disable=SC2086
    "$bounce" render "$scene" "${size[@]}" $lighting "${flags[@]}" --gi-warmup "${WARMUP:-32}" --frames 1 --hdr \
      --out "$dir/$variant" > "$dir/$variant.log"
  done
  row="| $name"
  for signal in diffuse specular; do
    stage=$dir/denoised/stages/$frame.gi.$signal.resolve.gOut_$([ $signal = diffuse ] && echo Diffuse || echo Specular).exr
    reference=$dir/ref.indirect-$signal.exr
    raw=$(field "$reference" "$stage" relMSE)
    filtered=$(field "$reference" "$dir/filters/frames/$frame.indirect-$signal.exr" relMSE)
    denoised=$(field "$reference" "$dir/denoised/frames/$frame.indirect-$signal.exr" relMSE)
    row+=" | $raw, $filtered, **$denoised** | $(awk -v a="$denoised" -v b="$raw" 'BEGIN { printf "%.3f", a / b }')"
  done
  echo "$row |" >> "$summary"
done
cat "$summary"
