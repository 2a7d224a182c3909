#!/usr/bin/env bash
# scripts/measure.sh, the harness that remakes the docs' headline tables, on
# cornell at a tiny size on whatever device runs the tests: both tables are
# written, with a row for each mode and warm-up, every cell a finite number,
# and bad arguments are refused with exit 2 before anything runs.
#   tests/measure_harness_check.sh BOUNCE_BINARY
set -euo pipefail
bounce=${1:?usage: tests/measure_harness_check.sh BOUNCE_BINARY}
root="$(cd "$(dirname "$0")/.." && pwd)"
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

# refused WORDS...: the harness, given exactly these arguments, exits 2 with
# its own message (naming the script, not bash's "line N") and runs nothing.
refused() {
  local shown="$*"
  if BOUNCE=$bounce "$root/scripts/measure.sh" "$@" > "$out/bad.log" 2>&1; then
    fail "scripts/measure.sh accepted '$shown'"
  else
    [ $? -eq 2 ] || fail "'$shown' did not exit with 2: $(cat "$out/bad.log")"
  fi
  grep -q "^scripts/measure.sh:" "$out/bad.log" || fail "'$shown' gave no message naming the script: $(cat "$out/bad.log")"
  grep -q "line [0-9]" "$out/bad.log" && fail "'$shown' gave bash's own message: $(cat "$out/bad.log")"
  [ ! -e "$out/bad" ] || fail "'$shown' made its output folder"
}
refused "$out/bad" --protocols timing,speed
refused "$out/bad" --scenes "$out/missing"
refused "$out/bad" --frobnicate
refused
refused --protocols timing
refused "$out/bad" --protocols ""
refused "$out/bad" --protocols ,
refused "$out/bad" --protocols
refused "$out/bad" --scenes
refused "$out/bad" --scenes --protocols timing
ONLY=nowhere BOUNCE=$bounce "$root/scripts/measure.sh" "$out/bad" > "$out/bad.log" 2>&1 && fail "ONLY=nowhere was accepted"

BOUNCE=$bounce ONLY=cornell WIDTH=32 HEIGHT=18 REFERENCE_SPP=2 WARMUPS="1 2" BENCH_WIDTH=32 BENCH_HEIGHT=18 \
  BENCH_WARMUP=1 BENCH_FRAMES=2 "$root/scripts/measure.sh" "$out/run" > "$out/run.log" 2>&1 ||
  fail "the harness failed: $(tail -5 "$out/run.log")"
number='[0-9]+(\.[0-9]+)?(e[-+]?[0-9]+)?'
grep -Eq "^\| cornell \| $number \| $number \|$" "$out/run/timing.md" || fail "timing.md has no cornell row: $(cat "$out/run/timing.md")"
for row in "hybrid \| 1" "hybrid \| 2" "screen-only \| 1"; do
  grep -Eq "^\| cornell \| $row( \| $number){5} \|$" "$out/run/quality.md" ||
    fail "quality.md has no row 'cornell | $row' of five numbers: $(cat "$out/run/quality.md")"
done
[ "$(grep -c '^| cornell' "$out/run/quality.md")" -eq 3 ] || fail "quality.md should have three cornell rows"
grep -q "^| pillars" "$out/run/quality.md" && fail "ONLY=cornell measured pillars too"
# Only frame 32 of each render is kept.
[ "$(find "$out/run/cornell/hybrid-1/frames" -name 'frame0032.exr' | wc -l)" -eq 1 ] || fail "frame 32 was not kept"
[ "$(find "$out/run/cornell/hybrid-1/frames" -name 'frame0031*' | wc -l)" -eq 0 ] || fail "frames before 32 were kept"
echo "measure harness: both tables written"
