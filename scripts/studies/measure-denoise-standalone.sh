#!/usr/bin/env bash
# The denoiser on its own (issue 14, "standalone"): `bounce denoise` feeds
# it the reference path tracer's 1-spp indirect diffuse and specular of a
# camera path, as an engine would its own signals, and measures the last
# frame against a converged reference. The issue's bar: cornell's sequence
# denoised to at most 1/10 of its input's relMSE after 32 frames. Needs a
# GPU (an hour or more on lavapipe).
#
#   scripts/studies/measure-denoise-standalone.sh OUT_DIR [SCENES_DIR]
#
# For cornell, pillars, sun-room and (when SCENES_DIR has them) Sponza and
# the Breakfast Room at 640x360 (WIDTH, HEIGHT), FRAMES frames (default 32)
# at SPP samples a frame (default 1), the reference at REFERENCE_SPP
# (default 512), seed 7; each with the scene's default (static) view and
# with the dolly: relMSE of the noisy input and of the denoised output per
# signal and of the whole frame, and their ratio. Extra `bounce denoise`
# flags (e.g. --gi.denoise.anti_firefly off) go in DENOISE_FLAGS. Writes
# OUT_DIR/summary.md (and each run's images and denoise.json in
# OUT_DIR/SCENE/CAMERA/).
set -euo pipefail
out=${1:?usage: scripts/studies/measure-denoise-standalone.sh OUT_DIR [SCENES_DIR]}
scenes_dir=${2:-}
: "${REFERENCE_SPP:=512}"
frames=${FRAMES:-32}
frame_spp=${SPP:-1}
# shellcheck source=scripts/measure-common.sh
source "$(dirname "$0")/../measure-common.sh"

# "noisy denoised ratio" of one row (indirect diffuse, indirect specular,
# frame) of the table bounce denoise prints.
row() { awk -v want="$2" '($1 " " $2 == want && NF == 5) || ($1 == want && NF == 4) { print $(NF - 2), $(NF - 1), $NF }' "$1"; }
cell() { read -r noisy denoised ratio <<< "$1"; printf '%s, %s, **%s**' "$noisy" "$denoised" "$ratio"; }

{
  echo "bounce denoise: $frames frames at $frame_spp spp, ${size[*]}, reference $spp spp, seed 7 ${DENOISE_FLAGS:-}"
  echo
  echo "| scene | camera | indirect diffuse relMSE: noisy, denoised, ratio | indirect specular: noisy, denoised, ratio | frame: noisy, denoised, ratio |"
  echo "|---|---|---|---|---|"
} >> "$summary"
for entry in "${entries[@]}"; do
  IFS='|' read -r name scene lighting <<< "$entry"
  for camera in default dolly; do
    dir="$out/$name/$camera"
    mkdir -p "$dir"
    camera_flags=()
    [ "$camera" = dolly ] && camera_flags=(--camera dolly)
    # shellcheck disable=SC2086
    "$bounce" denoise "$scene" "${size[@]}" $lighting "${camera_flags[@]}" --frames "$frames" --spp "$frame_spp" \
      --reference-spp "$spp" --seed 7 ${DENOISE_FLAGS:-} --out "$dir" > "$dir/denoise.log"
    printf '| %s | %s | %s | %s | %s |\n' "$name" "$camera" \
      "$(cell "$(row "$dir/denoise.log" "indirect diffuse")")" \
      "$(cell "$(row "$dir/denoise.log" "indirect specular")")" \
      "$(cell "$(row "$dir/denoise.log" frame)")" >> "$summary"
  done
done
cat "$summary"
