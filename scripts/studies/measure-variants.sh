#!/usr/bin/env bash
# Settings side by side against the reference path tracer: for choosing a
# default by measurement. Needs a GPU.
#
#   scripts/studies/measure-variants.sh OUT_DIR SCENES_DIR 'label|flags' ['label|flags' ...]
#
# For every scene of measure-common.sh (SCENES_DIR may be ''), the
# reference once, then `bounce render` (640x360, frame WARMUP: 32 unless the
# variable says otherwise; default view) once per variant with its flags
# added to the defaults: indirect specular and
# diffuse mean / reference and relMSE, and the whole frame's HDR-FLIP.
# Writes OUT_DIR/summary.md.
set -euo pipefail
out=${1:?usage: scripts/studies/measure-variants.sh OUT_DIR SCENES_DIR 'label|flags' ...}
scenes_dir=${2?usage: scripts/studies/measure-variants.sh OUT_DIR SCENES_DIR 'label|flags' ...}
shift 2
[ $# -gt 0 ] || { echo "measure-variants.sh: no variants given ('label|flags')" >&2; exit 2; }
# shellcheck source=scripts/measure-common.sh
source "$(dirname "$0")/../measure-common.sh"

echo "| scene | variant | specular mean / ref | specular relMSE | diffuse mean / ref | diffuse relMSE | frame FLIP |" >> "$summary"
echo "|---|---|---|---|---|---|---|" >> "$summary"
for entry in "${entries[@]}"; do
  scene_reference "$entry"
  for variant in "$@"; do
    IFS='|' read -r label flags <<< "$variant"
    # shellcheck disable=SC2086
    "$bounce" render "$scene" "${size[@]}" $lighting $flags --gi-warmup "${WARMUP:-32}" --frames 1 --hdr \
      --out "$dir/$label" > "$dir/$label.log"
    frame="$dir/$label/frames/frame0000"
    printf '| %s | %s | %s | %s | %s | %s | %s |\n' "$name" "$label" \
      "$(field "$dir/ref.indirect-specular.exr" "$frame.indirect-specular.exr" mean)" \
      "$(field "$dir/ref.indirect-specular.exr" "$frame.indirect-specular.exr" relMSE)" \
      "$(field "$dir/ref.indirect-diffuse.exr" "$frame.indirect-diffuse.exr" mean)" \
      "$(field "$dir/ref.indirect-diffuse.exr" "$frame.indirect-diffuse.exr" relMSE)" \
      "$(field "$dir/ref.exr" "$frame.exr" FLIP)" >> "$summary"
  done
done
cat "$summary"
