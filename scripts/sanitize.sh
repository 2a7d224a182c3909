#!/usr/bin/env bash
# The sanitizer job: builds Bounce with AddressSanitizer and
# UndefinedBehaviorSanitizer in ./build-sanitize and runs the CPU tests and
# the bad-input corpus there (the corpus drives the sanitized bounce command;
# lavapipe does the little GPU work it needs). Any sanitizer report fails the
# test it happens in. Leaks inside the Vulkan driver and LLVM are suppressed
# by tests/sanitizer-suppressions.txt, which names driver libraries only.
set -euo pipefail
cd "$(dirname "$0")/.."
build=build-sanitize
# The main build's shader cache, when there is one: the same shaders, already
# compiled by its test run (a cold compile on lavapipe is what takes time).
cache=()
[ -d build/mesa_shader_cache ] && cache=(-DBOUNCE_SHADER_CACHE_DIR="$PWD/build/mesa_shader_cache")
# -O1 -g1: AddressSanitizer's usual optimisation, and line tables for its
# stack traces without the full debug information of every template, which
# at -O2 -g made this build 2.3 times slower (CLI11 and gtest are compiled
# anew in every file that uses them).
started=$SECONDS
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
  -DBOUNCE_SANITIZE=ON --log-level=WARNING "${cache[@]}"
# Everything the CPU tests and the corpus run: their test programs (listed by
# tests/CMakeLists.txt) and bounce.
mapfile -t targets < "$build/sanitizer-targets.txt"
cmake --build "$build" --target bounce "${targets[@]}"
scripts/record-phase.sh "sanitizer build" $((SECONDS - started))
export ASAN_OPTIONS=detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1
export LSAN_OPTIONS="suppressions=$PWD/tests/sanitizer-suppressions.txt:print_suppressions=0"
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
# When the main build's test run has warmed the cache it shares (every
# class's stamp is there), warming it again would compile nothing: the
# corpus runs without those set-ups.
skip_warm=()
if [ ${#cache[@]} -gt 0 ] && [ -f build/shader-cache-stamps.txt ]; then
  skip_warm=(-FS shader_cache)
  while read -r stamp; do
    [ -f "build/mesa_shader_cache/$stamp" ] || skip_warm=()
  done < build/shader-cache-stamps.txt
fi
started=$SECONDS
status=0
ctest --test-dir "$build" -L 'cpu|corpus' "${skip_warm[@]}" --output-on-failure -j2 || status=$?
scripts/record-phase.sh "sanitizer suite" $((SECONDS - started))
exit $status
