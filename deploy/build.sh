#!/usr/bin/env bash
# Installs what is missing, then builds everything with CMake: the C++ targets (Release, into
# build/) and the dashboard (web/dist, target incise_web). Incremental: a second run only
# rebuilds what changed.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"

bash deploy/install-deps.sh

build_dir=${INCISE_BUILD_DIR:-build}
if [ ! -f "$build_dir/build.ninja" ]; then
  cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release -DINCISE_WERROR=ON
fi
cmake --build "$build_dir" -j"$(nproc)"
