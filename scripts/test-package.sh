#!/usr/bin/env bash
# The GI library as an outside project gets it (ctest runs this as the test
# "package"): usage  scripts/test-package.sh BUILD_DIR
#  1. cmake --install BUILD_DIR into a temporary prefix: exactly the public
#     headers, the static library and the CMake package files;
#  2. examples/minimal built against that prefix with find_package(bounce 0.2)
#     and run (its own device, validation and synchronization validation on:
#     it fails on any message, and unless the floor is lit);
#  3. nm: neither the example nor libbounce_gi.a holds or needs OpenEXR,
#     tinygltf, stb, CLI11 or the renderer (the library's link is its own);
#  4. the same example in a project that add_subdirectory()s this repository.
# Everything is written under one temporary folder, removed on exit.
set -euo pipefail
build=$(realpath "${1:?usage: scripts/test-package.sh BUILD_DIR}")
source=$(realpath "$(dirname "$0")/..")
work=$(mktemp -d "${TMPDIR:-/tmp}/bounce-package.XXXXXX")
trap 'rm -rf "$work"' EXIT
fail() { echo "package: FAILED: $*" >&2; exit 1; }
step() { echo "== $*"; }

step "install into $work/prefix"
cmake --install "$build" --prefix "$work/prefix" > "$work/install.log"
# (bounceTargets-<config>.cmake is named after the build type.)
installed=$(cd "$work/prefix" && find . -type f | sed 's/bounceTargets-[a-z]*\.cmake/bounceTargets-CONFIG.cmake/' | sort |
  tr '\n' ' ')
expected="./include/bounce/gi.h ./include/bounce/gi_settings.h ./include/bounce/version.h \
./lib/cmake/bounce/bounceConfig.cmake ./lib/cmake/bounce/bounceConfigVersion.cmake \
./lib/cmake/bounce/bounceTargets-CONFIG.cmake ./lib/cmake/bounce/bounceTargets.cmake ./lib/libbounce_gi.a "
[ "$installed" = "$expected" ] || fail "installed files are: $installed; expected: $expected"

step "examples/minimal with find_package(bounce 0.2)"
cmake -S "$source/examples/minimal" -B "$work/example" -DCMAKE_PREFIX_PATH="$work/prefix" \
  -DCMAKE_BUILD_TYPE=Release > "$work/configure.log" 2>&1 || { cat "$work/configure.log"; fail "configuring the example"; }
cmake --build "$work/example" > "$work/build.log" 2>&1 || { cat "$work/build.log"; fail "building the example"; }
"$work/example/bounce_minimal" || fail "the example (installed package) failed"

step "nm: no image-file, glTF, CLI or renderer code in the consumer"
forbidden='Imf_|Imath|openexr|tinygltf|stbi|stbiw|CLI::|bounce::io::|bounce::render::|bounce::scene::'
for binary in "$work/example/bounce_minimal" "$work/prefix/lib/libbounce_gi.a"; do
  found=$(nm -C "$binary" 2>/dev/null | grep -E "$forbidden" | head -5 || true)
  [ -z "$found" ] || fail "$(basename "$binary") holds or needs: $found"
done
# A check that could not fail would prove nothing: the library does hold its own code.
nm -C "$work/prefix/lib/libbounce_gi.a" | grep 'bounce::gi::GiContext::record' > /dev/null || fail "nm found no GiContext::record"

step "examples/minimal in a project that add_subdirectory()s the repository"
mkdir -p "$work/sub"
cat > "$work/sub/CMakeLists.txt" <<EOF
cmake_minimum_required(VERSION 3.22)
project(bounce_subdirectory LANGUAGES CXX)
add_subdirectory("$source" bounce)
if(TARGET bounce)
  message(FATAL_ERROR "the tools were built although bounce is not the top-level project")
endif()
add_executable(bounce_minimal "$source/examples/minimal/main.cpp")
target_compile_features(bounce_minimal PRIVATE cxx_std_20)
target_link_libraries(bounce_minimal PRIVATE bounce::gi)
EOF
cmake -S "$work/sub" -B "$work/sub/build" > "$work/sub.log" 2>&1 || { cat "$work/sub.log"; fail "configuring add_subdirectory"; }
cmake --build "$work/sub/build" -j2 > "$work/sub-build.log" 2>&1 || { tail -30 "$work/sub-build.log"; fail "building via add_subdirectory"; }
"$work/sub/build/bounce_minimal" > /dev/null || fail "the example (add_subdirectory) failed"
echo "package: OK"
