#!/usr/bin/env bash
# The specular branch's studies of docs/quality.md ("Indirect specular:
# rings, sampling, moving camera"). Needs a GPU (hours on lavapipe).
#
#   scripts/studies/measure-specular-study.sh OUT_DIR rings|sampling|dolly
#
#   rings     pillars, default view: each gold ring's (roughness 0.2 to 1.0)
#             indirect specular mean / reference and relMSE, at frame 1 and
#             frame 32, with reuse and without (--gi.restir off).
#   sampling  pillars along the orbit path, 32 frames from a cold start:
#             VNDF reservoirs against Zyanide's uniform-lobe reservoirs with a
#             disposable BRDF-target one, per ring, at frame 32 (the view
#             changed every frame).
#   dolly     sun-room along the dolly path (--fps 8: 16 frames move the
#             camera a quarter of the way to its target) after 16 still
#             frames, the oak floor at roughness 0.1, 0.3, 0.5, 0.8: the
#             floor's indirect specular relMSE against a reference of every
#             second frame, surface-only against dual-source reprojection.
#
# REFERENCE_SPP (default 512), WIDTH x HEIGHT (640x360). Writes
# OUT_DIR/summary.md.
set -euo pipefail
out=${1:?usage: scripts/studies/measure-specular-study.sh OUT_DIR rings|sampling|dolly}
study=${2:?usage: scripts/studies/measure-specular-study.sh OUT_DIR rings|sampling|dolly}
scenes_dir=
# shellcheck source=scripts/measure-common.sh
source "$(dirname "$0")/../measure-common.sh"
spp=${REFERENCE_SPP:-512}

# "roughness ratio relMSE" per gold ring of pillars (objects 3 to 7, roughness 0.2 to 1.0).
rings() {
  "$bounce" compare "$1" "$2" --regions "$3" |
    awk '$1 == "region" { object = int($2 / 65536); if (object >= 3 && object <= 7) printf "%.1f %.3f %.3f\n", 0.2 * (object - 2), $4, $5 }'
}

# One markdown row per ring: "| roughness | a ratio, a relMSE | b ... |" from several rings() outputs.
ring_rows() {
  paste -d' ' "$@" | awk '{ row = "| " $1; for (i = 1; i <= NF; i += 3) row = row " | " $(i + 1) ", " $(i + 2); print row " |" }'
}

case "$study" in
rings)
  dir="$out/rings"
  mkdir -p "$dir"
  "$bounce" reference pillars "${size[@]}" --spp "$spp" --seed 7 --out "$dir/ref.exr" > "$dir/ref.log"
  columns=()
  for frame in 1 32; do
    for mode in reuse noreuse; do
      flags=()
      [ "$mode" = noreuse ] && flags=(--gi.restir off)
      run="$dir/$mode-$frame"
      "$bounce" render pillars "${size[@]}" "${flags[@]}" --gi-warmup $((frame - 1)) --frames 1 --hdr --out "$run" \
        > "$run.log"
      rings "$dir/ref.indirect-specular.exr" "$run/frames/frame0000.indirect-specular.exr" \
        "$dir/ref.gbuffer/ids.exr" > "$run.rings"
      columns+=("$run.rings")
    done
  done
  {
    echo "| ring roughness | frame 1, reuse: mean / ref, relMSE | frame 1, no reuse | frame 32, reuse | frame 32, no reuse |"
    echo "|---|---|---|---|---|"
    ring_rows "${columns[@]}"
  } >> "$summary"
  ;;
sampling)
  dir="$out/sampling"
  mkdir -p "$dir"
  "$bounce" reference pillars "${size[@]}" --camera orbit --frame 32 --spp "$spp" --seed 7 --out "$dir/ref.exr" \
    > "$dir/ref.log"
  columns=()
  for sampling in vndf uniform; do
    run="$dir/$sampling"
    "$bounce" render pillars "${size[@]}" --camera orbit --gi-warmup 0 --frames 33 --hdr \
      --gi.specular.sampling "$sampling" --out "$run" > "$run.log"
    rings "$dir/ref.indirect-specular.exr" "$run/frames/frame0032.indirect-specular.exr" \
      "$dir/ref.gbuffer/ids.exr" > "$run.rings"
    columns+=("$run.rings")
  done
  {
    echo "| ring roughness | VNDF reservoirs: mean / ref, relMSE | uniform + disposable reservoirs: mean / ref, relMSE |"
    echo "|---|---|---|"
    ring_rows "${columns[@]}"
  } >> "$summary"
  ;;
dolly)
  echo "| floor roughness | surface-only reprojection: mean relMSE, mean / ref | dual-source: mean relMSE, mean / ref |" >> "$summary"
  echo "|---|---|---|" >> "$summary"
  for roughness in 0.1 0.3 0.5 0.8; do
    dir="$out/dolly-$roughness"
    mkdir -p "$dir"
    common=(sun-room "${size[@]}" --camera dolly --fps 8 --material "oak floor:roughness=$roughness")
    for frame in 2 4 6 8 10 12 14 16; do
      "$bounce" reference "${common[@]}" --frame "$frame" --spp "$spp" --seed 7 --out "$dir/ref$frame.exr" \
        > "$dir/ref$frame.log"
    done
    row="| $roughness"
    for reprojection in surface dual; do
      run="$dir/$reprojection"
      "$bounce" render "${common[@]}" --gi-warmup 16 --frames 17 --hdr --gi.specular.reprojection "$reprojection" \
        --out "$run" > "$run.log"
      for frame in 2 4 6 8 10 12 14 16; do
        # The floor: object 0, material 0 (label 0).
        "$bounce" compare "$dir/ref$frame.indirect-specular.exr" \
          "$run/frames/$(printf 'frame%04d' "$frame").indirect-specular.exr" --regions "$dir/ref$frame.gbuffer/ids.exr" |
          awk '$1 == "region" && $2 == 0 { print $4, $5 }'
      done > "$run.floor"
      row="$row | $(awk '{ ratio += $1; error += $2 } END { printf "%.4f, %.3f", error / NR, ratio / NR }' "$run.floor")"
    done
    echo "$row |" >> "$summary"
  done
  ;;
*)
  echo "measure-specular-study.sh: unknown study '$study' (rings, sampling, dolly)" >&2
  exit 2
  ;;
esac
cat "$summary"
