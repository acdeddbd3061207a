#!/usr/bin/env bash
# Installs what is missing, then builds everything with CMake: the C++ targets (Release, into
# build/) and the dashboard (web/dist, target incise_web). Incremental: a second run only
# rebuilds what changed.
#   INCISE_SANITIZED_TESTS=ON|OFF  also build the boundaries' sanitized tests (cmake/sanitized.cmake;
#                                  deploy/test.sh sets ON); unset keeps the build folder's choice.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"

bash deploy/install-deps.sh

build_dir=${INCISE_BUILD_DIR:-build}
if [ ! -f "$build_dir/build.ninja" ]; then
  cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release -DINCISE_WERROR=ON
fi
if [ -n "${INCISE_SANITIZED_TESTS:-}" ] &&
   ! grep -qx "INCISE_SANITIZED_TESTS:BOOL=$INCISE_SANITIZED_TESTS" "$build_dir/CMakeCache.txt"; then
  cmake "$build_dir" -DINCISE_SANITIZED_TESTS="$INCISE_SANITIZED_TESTS"
fi
cmake --build "$build_dir" -j"$(nproc)"
