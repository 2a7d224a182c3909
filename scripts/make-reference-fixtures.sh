#!/usr/bin/env bash
# Regenerates the converged path-traced references the GI stages are judged
# against: each built-in scene below at 640x360 from its default camera,
# sampled until the two independent halves of the samples agree to relMSE
# < 1e-3 (checked at every power of two spp). They are large, so they are not
# committed: the fixed seed makes this script give the same images again.
# Takes about a minute per scene on a recent GPU; far longer on lavapipe.
#
#   scripts/make-reference-fixtures.sh [OUT_DIR] [SCENE...]
#
# Writes OUT_DIR/SCENE/reference.exr with its parts, G-buffer, sheet and a
# .json that records the spp it took. BOUNCE overrides the binary, MAX_SPP
# the most samples per pixel it may take (default 65536).
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-out/fixtures}
shift || true
scenes=("$@")
[ ${#scenes[@]} -gt 0 ] || scenes=(cornell sun-room)
bounce=${BOUNCE:-./build/bounce}
[ -x "$bounce" ] || { echo "make-reference-fixtures: $bounce not found; run scripts/build.sh first" >&2; exit 1; }
for scene in "${scenes[@]}"; do
  "$bounce" reference "$scene" --width 640 --height 360 --spp "${MAX_SPP:-65536}" --target-relmse 1e-3 --seed 1 \
    --out "$out/$scene/reference.exr"
done
