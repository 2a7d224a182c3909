#!/usr/bin/env bash
# The whole test suite, as CI runs it (README's test command calls this after
# building): every test on lavapipe with the validation layer, then the
# sanitizer job; after each, the ten slowest tests, warning about any that
# took more than a quarter of its timeout (the target) and failing if any
# took more than half of it. Exits non-zero if anything failed, after
# running everything, and then names what failed last of all: CI shows only
# the end of the output, and a failure of the first run would otherwise
# scroll away under the sanitizer job's.
set -uo pipefail
cd "$(dirname "$0")/.."
failed=()
failed_builds=()
started=$SECONDS
ctest --test-dir build --output-on-failure -j2 || { failed+=("the test suite (build)"); failed_builds+=(build); }
scripts/record-phase.sh "main suite" $((SECONDS - started))
./scripts/slowest-tests.sh build || failed+=("scripts/slowest-tests.sh build")
./scripts/sanitize.sh || { failed+=("the sanitizer job (build-sanitize)"); failed_builds+=(build-sanitize); }
if [ -f build-sanitize/Testing/Temporary/CTestCostData.txt ]; then
  ./scripts/slowest-tests.sh build-sanitize || failed+=("scripts/slowest-tests.sh build-sanitize")
fi
[ ${#failed[@]} -eq 0 ] && exit 0
echo
echo "FAILED: ${failed[*]}"
for build in "${failed_builds[@]}"; do
  list="$build/Testing/Temporary/LastTestsFailed.log"
  [ -s "$list" ] || continue
  echo "failed tests in $build (number:name; their output is above, under ***Failed):"
  sed 's/^/  /' "$list"
done
exit 1
