#!/usr/bin/env bash
# Ghosting (issue 14, "No ghosting"): after a fast turn and after a moving
# object passes, does the error of the newly uncovered pixels return to the
# level of the rest within a few frames? `bounce ghosting` for both events
# at 640x360 (WIDTH, HEIGHT), with the default settings and with the
# denoiser off (--gi.denoise.enabled off, today's temporal filters): the
# fast turn in sun-room (20 degrees in one frame at frame 32, after 32
# warm-up frames) and the sliding box of sun-room-animated (the strips it
# uncovers at frames 32-39), each frame against a REFERENCE_SPP (default
# 256) reference. Needs a GPU (hours on lavapipe).
#
#   scripts/studies/measure-ghosting.sh OUT_DIR
#
# Extra `bounce ghosting` flags go in GHOSTING_FLAGS. Writes OUT_DIR/summary.md
# (the verdicts, then every table) and each run's ghosting.json, ghosting.png
# (error against frames since uncovered) and regions.png in
# OUT_DIR/EVENT-SETTINGS/.
set -euo pipefail
out=${1:?usage: scripts/studies/measure-ghosting.sh OUT_DIR}
scenes_dir=""
: "${REFERENCE_SPP:=256}"
# shellcheck source=scripts/measure-common.sh
source "$(dirname "$0")/../measure-common.sh"

{
  echo "bounce ghosting: ${size[*]}, references $spp spp, seed 7 ${GHOSTING_FLAGS:-}"
  echo
  echo "| event | settings | uncovered pixels within 1.5 x the rest (frame, indirect diffuse, indirect specular) | x the nearby rest | x their own settled error |"
  echo "|---|---|---|---|---|"
} >> "$summary"
# "+k, +k, +k" (or "never") of one verdict of the JSON, for the frame and both signals.
verdict() {
  python3 -c 'import json, sys
r = json.load(open(sys.argv[1]))["recovered_after"][sys.argv[2]]
print(", ".join("-" if r is None else ("never" if r[k] is None else "+%d" % r[k])
                for k in ("frame", "indirect_diffuse", "indirect_specular")) if r else "-")' "$1" "$2"
}
for event in turn object; do
  for setting in default denoiser-off; do
    dir="$out/$event-$setting"
    mkdir -p "$dir"
    flags=()
    [ "$setting" = denoiser-off ] && flags=(--gi.denoise.enabled off)
    # shellcheck disable=SC2086
    "$bounce" ghosting --event "$event" "${size[@]}" --reference-spp "$spp" --seed 7 "${flags[@]}" \
      ${GHOSTING_FLAGS:-} --out "$dir" > "$dir/ghosting.log"
    json="$dir/ghosting.json"
    printf '| %s | %s | %s | %s | %s |\n' "$event" "$setting" "$(verdict "$json" rest)" "$(verdict "$json" nearby)" \
      "$(verdict "$json" own_settled)" >> "$summary"
  done
done
for event in turn object; do
  for setting in default denoiser-off; do
    {
      echo
      echo "## $event, $setting"
      echo
      echo '```'
      sed -n '/newly uncovered/,$p' "$out/$event-$setting/ghosting.log"
      echo '```'
    } >> "$summary"
  done
done
cat "$summary"
