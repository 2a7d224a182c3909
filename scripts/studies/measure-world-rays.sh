#!/usr/bin/env bash
# What world rays cost and what they are worth, per variant of the
# settings: the numbers of docs/benchmarks.md, "World rays" (issue 29).
# Needs a GPU.
#
#   scripts/studies/measure-world-rays.sh OUT_DIR SCENES_DIR 'label|flags' ['label|flags' ...]
#
# For every scene of measure-common.sh (SCENES_DIR may be ''), per variant
# (its flags added to the defaults):
#   speed    `bounce bench` at 1920x1080, --warmup 30 --frames 150: the
#            whole GI (every gi.* pass's median, added) and the world rays
#            per pixel and frame it counted; SPEED=0 skips it
#   quality  the reference (640x360, frame 32 of the default camera, 1024
#            spp, seed 7) against `bounce render --gi-warmup 64 --frames 33`
#            (frame 32): whole-frame HDR-FLIP, and the whole frame's, the
#            indirect diffuse's and the indirect specular's mean / reference;
#            QUALITY=0 skips it; WARMUP changes the 64
# Writes OUT_DIR/summary.md; each bench's JSON and log stay in OUT_DIR/NAME/.
set -euo pipefail
out=${1:?usage: scripts/studies/measure-world-rays.sh OUT_DIR SCENES_DIR 'label|flags' ...}
scenes_dir=${2?usage: scripts/studies/measure-world-rays.sh OUT_DIR SCENES_DIR 'label|flags' ...}
shift 2
[ $# -gt 0 ] || { echo "measure-world-rays.sh: no variants given ('label|flags')" >&2; exit 2; }
# shellcheck source=scripts/measure-common.sh
source "$(dirname "$0")/../measure-common.sh"

echo "| scene | variant | whole GI ms (1080p) | world rays / pixel | frame FLIP | frame mean / ref | diffuse mean / ref | specular mean / ref |" >> "$summary"
echo "|---|---|---:|---:|---:|---:|---:|---:|" >> "$summary"
for entry in "${entries[@]}"; do
  IFS='|' read -r name scene lighting <<< "$entry"
  dir="$out/$name"
  mkdir -p "$dir"
  if [ "${QUALITY:-1}" != 0 ]; then scene_reference "$entry" --frame 32; fi
  for variant in "$@"; do
    IFS='|' read -r label flags <<< "$variant"
    gi_ms=- rays=- flip=- whole=- diffuse=- specular=-
    if [ "${SPEED:-1}" != 0 ]; then
      # shellcheck disable=SC2086
      "$bounce" bench "$scene" --width 1920 --height 1080 --warmup 30 --frames 150 --rays 0 --copy-mb 0 $lighting $flags \
        --json "$dir/$label.bench.json" > "$dir/$label.bench.log"
      gi_ms=$(awk '/^whole GI/ { print $(NF - 1) }' "$dir/$label.bench.log")
      rays=$(awk '$1 == "total" && /per pixel/ { print $3 }' "$dir/$label.bench.log")
    fi
    if [ "${QUALITY:-1}" != 0 ]; then
      # shellcheck disable=SC2086
      "$bounce" render "$scene" "${size[@]}" $lighting $flags --gi-warmup "${WARMUP:-64}" --frames 33 --hdr \
        --out "$dir/$label" > "$dir/$label.log"
      frame="$dir/$label/frames/frame0032"
      flip=$(field "$dir/ref.exr" "$frame.exr" FLIP)
      whole=$(field "$dir/ref.exr" "$frame.exr" mean)
      diffuse=$(field "$dir/ref.indirect-diffuse.exr" "$frame.indirect-diffuse.exr" mean)
      specular=$(field "$dir/ref.indirect-specular.exr" "$frame.indirect-specular.exr" mean)
    fi
    printf '| %s | %s | %s | %s | %s | %s | %s | %s |\n' "$name" "$label" "$gi_ms" "$rays" "$flip" "$whole" "$diffuse" \
      "$specular" >> "$summary"
  done
done
cat "$summary"
