#!/usr/bin/env bash
# Measures the GI library against the reference path tracer and times it:
# the numbers of docs/quality.md and docs/benchmarks.md. Needs a GPU to
# finish in minutes (a few hours on lavapipe).
#
#   scripts/studies/measure-gi.sh OUT_DIR [SPONZA.gltf]
#
# For cornell, sun-room and (when given) Sponza at 640x360:
#   - references of the default view and of frame 32 of the dolly path;
#   - "frame 1": the first frame after a cut to the same view, after 64
#     frames of warm-up (no reservoir or filter history; last frame's light);
#   - "after 32 frames": frame 32 of the dolly path (a slow move);
#   - stability: the change from frame 64 to 65 of the default (static) camera;
#   each with reuse and without (--gi.restir off);
# and GPU timings at 1920x1080 (bounce bench). Writes OUT_DIR/summary.md and
# everything it compared, plus pictures for the docs.
# BOUNCE overrides the binary, REFERENCE_SPP the references' samples, WIDTH
# and HEIGHT the comparison size, BENCH=0 skips the timings.
set -euo pipefail
out=${1:?usage: scripts/studies/measure-gi.sh OUT_DIR [SPONZA.gltf]}
sponza=${2:-}
bounce=${BOUNCE:-./build/bounce}
spp=${REFERENCE_SPP:-2048}
size=(--width "${WIDTH:-640}" --height "${HEIGHT:-360}")
mkdir -p "$out"
summary="$out/summary.md"
: > "$summary"

# "name|scene argument|extra flags"
scenes=("cornell|cornell|" "sun-room|sun-room|")
[ -n "$sponza" ] && scenes+=("sponza|$sponza|--sun-elevation 75 --sun-azimuth 100")

# One number from a compare run: the relMSE line or the mean ratio.
relmse() { "$bounce" compare "$1" "$2" | awk '/^relMSE/{print $2}'; }
ratio() { "$bounce" compare "$1" "$2" | awk '/^mean/{print $NF}'; }
change() { "$bounce" compare --sequence "$1" "$2" | awk '/^temporal/{print $5}'; }
divide() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.3f", (b > 0 ? a / b : 0) }'; }

echo "| scene | relMSE frame 1 (reuse / none / ratio) | relMSE after 32 dolly frames (reuse / none / ratio) | mean / reference (front, reuse) | frame-to-frame change after 64 static frames |" >> "$summary"
echo "|---|---|---|---|---|" >> "$summary"
for entry in "${scenes[@]}"; do
  IFS='|' read -r name scene extra <<< "$entry"
  dir="$out/$name"
  mkdir -p "$dir"
  lighting=$(echo "$extra" | sed 's/--gi[^ ]* [^ ]*//g')  # the reference takes the lighting flags only
  # shellcheck disable=SC2086
  "$bounce" reference "$scene" "${size[@]}" $lighting --spp "$spp" --seed 7 --out "$dir/ref-front.exr" > "$dir/ref-front.log"
  # shellcheck disable=SC2086
  "$bounce" reference "$scene" "${size[@]}" $lighting --camera dolly --frame 32 --spp "$spp" --seed 7 \
    --out "$dir/ref-dolly32.exr" > "$dir/ref-dolly32.log"
  for mode in reuse none; do
    flags=()
    [ "$mode" = none ] && flags=(--gi.restir off)
    # shellcheck disable=SC2086
    "$bounce" render "$scene" "${size[@]}" $extra "${flags[@]}" --gi-warmup 64 --frames 2 --cut-frames 1 --hdr \
      --out "$dir/cut-$mode" > "$dir/cut-$mode.log"
    # shellcheck disable=SC2086
    "$bounce" render "$scene" "${size[@]}" $extra "${flags[@]}" --camera dolly --gi-warmup 64 --frames 33 --hdr \
      --out "$dir/dolly-$mode" > "$dir/dolly-$mode.log"
    # shellcheck disable=SC2086
    "$bounce" render "$scene" "${size[@]}" $extra "${flags[@]}" --gi-warmup 0 --frames 66 --hdr \
      --out "$dir/static-$mode" > "$dir/static-$mode.log"
  done
  f1r=$(relmse "$dir/ref-front.indirect-diffuse.exr" "$dir/cut-reuse/frames/frame0001.indirect-diffuse.exr")
  f1n=$(relmse "$dir/ref-front.indirect-diffuse.exr" "$dir/cut-none/frames/frame0001.indirect-diffuse.exr")
  d32r=$(relmse "$dir/ref-dolly32.indirect-diffuse.exr" "$dir/dolly-reuse/frames/frame0032.indirect-diffuse.exr")
  d32n=$(relmse "$dir/ref-dolly32.indirect-diffuse.exr" "$dir/dolly-none/frames/frame0032.indirect-diffuse.exr")
  mean=$(ratio "$dir/ref-front.indirect-diffuse.exr" "$dir/static-reuse/frames/frame0065.indirect-diffuse.exr")
  stable=$(change "$dir/static-reuse/frames/frame0064.exr" "$dir/static-reuse/frames/frame0065.exr")
  printf '| %s | %s / %s / %s | %s / %s / %s | %s | %s |\n' "$name" "$f1r" "$f1n" "$(divide "$f1r" "$f1n")" \
    "$d32r" "$d32n" "$(divide "$d32r" "$d32n")" "$mean" "$stable" >> "$summary"
done

[ "${BENCH:-1}" = 0 ] && exit 0
echo >> "$summary"
echo "GPU timings, 1920x1080:" >> "$summary"
for entry in "${scenes[@]}"; do
  IFS='|' read -r name scene extra <<< "$entry"
  # shellcheck disable=SC2086
  "$bounce" bench "$scene" --width 1920 --height 1080 $extra --warmup 30 --frames 300 --rays 0 --copy-mb 512 \
    --json "$out/bench-$name.json" > "$out/bench-$name.txt"
  { echo; echo "$name:"; echo '```'; sed -n '/GPU time per pass/,$p' "$out/bench-$name.txt"; echo '```'; } >> "$summary"
done
cat "$summary"
