#!/usr/bin/env bash
# The measurement harness: the protocols behind the headline tables of
# docs/benchmarks.md and docs/quality.md, on the built-in scenes and (with
# --scenes) Sponza and the Breakfast Room, each with the lighting the docs
# use. Needs a GPU for the real sizes (lavapipe takes hours).
#
#   scripts/measure.sh OUT_DIR [--scenes DIR] [--protocols LIST]
#
# LIST is a comma list of (default: timing,quality):
#   timing   whole GI (the sum of every gi.* pass's median GPU time) of
#            `bounce bench SCENE --width 1920 --height 1080 --warmup 30
#            --frames 150 --rays 0 --copy-mb 0`, hybrid (the default scene
#            bridge) and screen-only (--scene-bridge none): OUT_DIR/timing.md
#   quality  `bounce reference SCENE --width 640 --height 360 --frame 32
#            --spp 1024 --seed 7` against frame 32 of `bounce render SCENE
#            --width 640 --height 360 --gi-warmup W --frames 33 --hdr` for
#            each W of WARMUPS (64: the issue's frame 32; 512: settled),
#            hybrid, and screen-only after the first W: indirect diffuse and
#            specular means over the reference's, their relMSE and the
#            frame's HDR-FLIP: OUT_DIR/quality.md
# Each table starts with the device and the command that made it; every
# run's output stays in OUT_DIR/SCENE/ (the images of the last frame).
#
# Environment (defaults are the docs' protocols): BOUNCE (./build/bounce),
# WIDTH, HEIGHT (640, 360), REFERENCE_SPP (1024), WARMUPS ("64 512"),
# BENCH_WIDTH, BENCH_HEIGHT (1920, 1080), BENCH_WARMUP (30), BENCH_FRAMES
# (150), ONLY (a comma list of scene names: cornell, pillars, sun-room,
# sponza, breakfast; default all). Extra flags for every render and bench (not the reference) go in
# GI_FLAGS, e.g. GI_FLAGS="--gi.cache.cell_size 0.02" to measure a variant.
set -euo pipefail
usage="usage: scripts/measure.sh OUT_DIR [--scenes DIR] [--protocols timing,quality]"
# Every mistake on the command line is one line naming it, exit 2, before
# anything runs (bash's own ${1:?} says "line 32" and nothing a user can act on).
refuse() {
  echo "scripts/measure.sh: $1; $usage" >&2
  exit 2
}
[ $# -gt 0 ] || refuse "no OUT_DIR given"
# An option in OUT_DIR's place means OUT_DIR was left out: its folder would be named "--scenes".
case "$1" in
  "") refuse "OUT_DIR is empty" ;;
  -*) refuse "OUT_DIR is missing ('$1' is an option; OUT_DIR comes first)" ;;
esac
out=$1
shift
scenes_dir=""
protocols="timing,quality"
while [ $# -gt 0 ]; do
  case "$1" in
    --scenes | --protocols)
      [ $# -ge 2 ] || refuse "$1 needs a value"
      [ -n "$2" ] || refuse "$1 is given an empty value"
      case "$2" in -*) refuse "$1 needs a value, not the option '$2'" ;; esac
      if [ "$1" = --scenes ]; then scenes_dir=$2; else protocols=$2; fi
      shift 2
      ;;
    *) refuse "unknown argument '$1'" ;;
  esac
done
chosen_protocols=0
for protocol in ${protocols//,/ }; do
  case "$protocol" in
    timing | quality) chosen_protocols=$((chosen_protocols + 1)) ;;
    *) echo "scripts/measure.sh: unknown protocol '$protocol' (timing, quality)" >&2; exit 2 ;;
  esac
done
[ "$chosen_protocols" -gt 0 ] || refuse "--protocols '$protocols' names no protocol (timing, quality)"
if [ -n "$scenes_dir" ] && [ ! -d "$scenes_dir" ]; then
  echo "scripts/measure.sh: --scenes $scenes_dir is not a folder" >&2
  exit 2
fi
# shellcheck source=scripts/measure-common.sh
source "$(dirname "$0")/measure-common.sh"
rm -f "$summary"  # measure-common's; this harness writes one file per protocol
if [ -n "${ONLY:-}" ]; then
  chosen=()
  for entry in "${entries[@]}"; do
    [[ ",$ONLY," == *",${entry%%|*},"* ]] && chosen+=("$entry")
  done
  [ ${#chosen[@]} -gt 0 ] || { echo "scripts/measure.sh: ONLY=$ONLY names none of the scenes" >&2; exit 2; }
  entries=("${chosen[@]}")
fi
read -r -a warmups <<< "${WARMUPS:-64 512}"
read -r -a gi_flags <<< "${GI_FLAGS:-}"
device=$("$bounce" info | awk -F': ' '/^selected:/ { print $NF }')
[ -n "$device" ] || { echo "scripts/measure.sh: '$bounce info' names no device" >&2; exit 1; }
when=$(date -u +%Y-%m-%d)

# Whole GI of one bench run, as bench adds it up ("whole GI (every gi.*
# pass, medians added): X ms"); none printed (no GI pass ran) fails.
whole_gi() {
  awk '/^whole GI/ { print $(NF - 1); found = 1 } END { exit !found }' "$1"
}

measure_timing() {
  local file="$out/timing.md" bw=${BENCH_WIDTH:-1920} bh=${BENCH_HEIGHT:-1080}
  local bench_flags=(--width "$bw" --height "$bh" --warmup "${BENCH_WARMUP:-30}" --frames "${BENCH_FRAMES:-150}"
    --rays 0 --copy-mb 0)
  {
    echo "Whole GI (the sum of every \`gi.*\` pass's median GPU time), ms, on $device, ${bw}x${bh}, $when:"
    echo "\`bounce bench SCENE ${bench_flags[*]}${GI_FLAGS:+ $GI_FLAGS}\` (hybrid) and the same with \`--scene-bridge none\`"
    echo "(screen-only). Made by \`scripts/measure.sh OUT --protocols timing\`."
    echo
    echo "| scene | hybrid | screen-only |"
    echo "|---|---|---|"
  } > "$file"
  for entry in "${entries[@]}"; do
    IFS='|' read -r name scene lighting <<< "$entry"
    dir="$out/$name"
    mkdir -p "$dir"
    local cells=()
    for bridge in bvh none; do
      # shellcheck disable=SC2086
      "$bounce" bench "$scene" "${bench_flags[@]}" $lighting --scene-bridge "$bridge" "${gi_flags[@]}" \
        > "$dir/bench-$bridge.txt"
      cells+=("$(whole_gi "$dir/bench-$bridge.txt")")
    done
    echo "| $name | ${cells[0]} | ${cells[1]} |" >> "$file"
  done
}

# "diffuse specular relMSE-diffuse relMSE-specular FLIP" of frame 32 of a
# render against the reference, rounded as the docs print them.
compare_frame() {
  local ref=$1 frame=$2
  printf '%.3f %.3f %.3g %.3g %.3f\n' "$(field "$ref.indirect-diffuse.exr" "$frame.indirect-diffuse.exr" mean)" \
    "$(field "$ref.indirect-specular.exr" "$frame.indirect-specular.exr" mean)" \
    "$(field "$ref.indirect-diffuse.exr" "$frame.indirect-diffuse.exr" relMSE)" \
    "$(field "$ref.indirect-specular.exr" "$frame.indirect-specular.exr" relMSE)" \
    "$(field "$ref.exr" "$frame.exr" FLIP)"
}

measure_quality() {
  local file="$out/quality.md"
  {
    echo "Indirect means over the reference's, relMSE and the frame's HDR-FLIP, frame 32, on $device, ${size[*]}, $when:"
    echo "\`bounce reference SCENE ${size[*]} --frame 32 --spp $spp --seed 7\` against frame 32 of"
    echo "\`bounce render SCENE ${size[*]} --gi-warmup W --frames 33 --hdr${GI_FLAGS:+ $GI_FLAGS}\` (hybrid; screen-only adds"
    echo "\`--scene-bridge none\`). Made by \`scripts/measure.sh OUT --protocols quality\`."
    echo
    echo "| scene | mode | warm-up | diffuse mean / ref | specular mean / ref | diffuse relMSE | specular relMSE | frame HDR-FLIP |"
    echo "|---|---|---|---|---|---|---|---|"
  } > "$file"
  for entry in "${entries[@]}"; do
    scene_reference "$entry" --frame 32
    local runs=()
    for warmup in "${warmups[@]}"; do runs+=("hybrid|$warmup|bvh"); done
    runs+=("screen-only|${warmups[0]}|none")
    for run in "${runs[@]}"; do
      IFS='|' read -r mode warmup bridge <<< "$run"
      render="$dir/$mode-$warmup"
      rm -rf "$render"
      # shellcheck disable=SC2086
      "$bounce" render "$scene" "${size[@]}" $lighting --gi-warmup "$warmup" --frames 33 --hdr \
        --scene-bridge "$bridge" "${gi_flags[@]}" --out "$render" > "$render.log"
      # Only frame 32 is measured: the other frames' images go.
      find "$render/frames" -type f ! -name 'frame0032*' -delete
      read -r diffuse specular relmse_diffuse relmse_specular flip < <(compare_frame "$dir/ref" "$render/frames/frame0032")
      echo "| $name | $mode | $warmup | $diffuse | $specular | $relmse_diffuse | $relmse_specular | $flip |" >> "$file"
    done
  done
}

for protocol in ${protocols//,/ }; do
  "measure_$protocol"
  cat "$out/$protocol.md"
  echo
done
