#!/usr/bin/env bash
# Runs every test: installs what is missing, builds, then CTest runs the unit tests, the
# integration tests (real server binary, real agent, real SQLite files), the browser test
# (Playwright driving Debian's Chromium) and the boundaries' tests again under AddressSanitizer and
# UndefinedBehaviorSanitizer (asan/*, cmake/sanitized.cmake). Exits non-zero on any failure.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"

start=$(date +%s)
INCISE_SANITIZED_TESTS=ON bash deploy/build.sh
build_dir=${INCISE_BUILD_DIR:-build}
ctest --test-dir "$build_dir" --output-on-failure -j"$(nproc)" --timeout 600
echo "deploy/test.sh: all tests passed in $(( $(date +%s) - start )) s"
