#!/usr/bin/env bash
# Configures and builds Bounce in ./build (Release, Ninja). Re-running only
# rebuilds what changed.
set -euo pipefail
cd "$(dirname "$0")/.."
started=$SECONDS
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release --log-level=WARNING
cmake --build build
scripts/record-phase.sh build $((SECONDS - started))
