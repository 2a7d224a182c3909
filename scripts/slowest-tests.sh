#!/usr/bin/env bash
# After a ctest run: prints the ten slowest tests (ctest's average time of
# each over its runs in this build) with the share of its timeout each used,
# then warns, naming them, about every test over a quarter of its timeout
# (the target every test is written to: on an idle machine it leaves room
# for one four times busier), and fails (exit 1) naming every test over
# half of it. CI machines are shared and sometimes busy: a test between a
# quarter and a half is a test to shrink, not a failed landing, while one
# over half is a step from its timeout.
#   scripts/slowest-tests.sh [BUILD_DIR]     (default: build)
set -euo pipefail
build=${1:-build}
costs="$build/Testing/Temporary/CTestCostData.txt"
if [ ! -f "$costs" ]; then
  echo "slowest-tests: $costs not found: run ctest in $build first" >&2
  exit 1
fi
timeouts=$(mktemp)
trap 'rm -f "$timeouts"' EXIT
# Each test's name and TIMEOUT from ctest's JSON listing (pretty-printed by
# CMake: test names sit at six spaces of indentation).
ctest --test-dir "$build" --show-only=json-v1 | awk '
  /^      "name" : "/ { sub(/^      "name" : "/, ""); sub(/",?$/, ""); test = $0 }
  /"name" : "TIMEOUT"/ { timeout = 1; next }
  timeout && /"value" :/ { sub(/.*"value" : /, ""); sub(/,$/, ""); print test "\t" $0; timeout = 0 }
' > "$timeouts"
# CTestCostData lines: NAME RUNS AVERAGE_SECONDS, then "---" and failed tests.
awk -v timeouts="$timeouts" '
  BEGIN { FS = "\t"; while ((getline line < timeouts) > 0) { split(line, f, "\t"); limit[f[1]] = f[2] }; FS = " " }
  /^---/ { exit }
  NF == 3 { printf "%s\t%.1f\t%s\n", $1, $3, ($1 in limit) ? limit[$1] : 1500 }
' "$costs" | sort -t$'\t' -k2,2 -rn > "$timeouts.sorted"
mv "$timeouts.sorted" "$timeouts"
echo "slowest tests (seconds, share of the test's timeout):"
head -n 10 "$timeouts" | awk -F'\t' '{ printf "  %7.1f s  %5.1f%%  %s\n", $2, 100 * $2 / $3, $1 }'
listOver() {  # the tests over 1/$1 of their timeout
  awk -F'\t' -v share="$1" '$2 > $3 / share { printf "  %s: %.1f s of a %.0f s timeout\n", $1, $2, $3 }' "$timeouts"
}
target=$(listOver 4)
over=$(listOver 2)
if [ -n "$target" ]; then
  echo "warning: these tests took more than a quarter of their timeout (the target; shrink them):"
  echo "$target"
fi
if [ -n "$over" ]; then
  echo "FAILED: these tests took more than half of their timeout:"
  echo "$over"
  exit 1
fi
