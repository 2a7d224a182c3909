#!/usr/bin/env bash
# The whole test suite, as CI runs it (README's test command calls this after
# building): every test on lavapipe with the validation layer, the ten
# slowest of them, then the sanitizer job. Exits non-zero if anything failed,
# after running everything.
set -uo pipefail
cd "$(dirname "$0")/.."
status=0
ctest --test-dir build --output-on-failure -j2 || status=1
./scripts/slowest-tests.sh build || status=1
./scripts/sanitize.sh || status=1
exit $status
