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
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DBOUNCE_SANITIZE=ON --log-level=WARNING "${cache[@]}"
# Everything the CPU tests and the corpus run: their test programs (listed by
# tests/CMakeLists.txt) and bounce.
mapfile -t targets < "$build/sanitizer-targets.txt"
cmake --build "$build" --target bounce "${targets[@]}"
export ASAN_OPTIONS=detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1
export LSAN_OPTIONS="suppressions=$PWD/tests/sanitizer-suppressions.txt:print_suppressions=0"
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
ctest --test-dir "$build" -L 'cpu|corpus' --output-on-failure -j2
