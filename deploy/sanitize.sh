#!/usr/bin/env bash
# The tests of the boundaries under AddressSanitizer and UndefinedBehaviorSanitizer
# (docs/fuzzing.md): builds the unit and integration tests of server/, db/, devices/ and
# curriculum/ and the tests of sim/'s parsers (meshes, scene files), with the server and agent
# they run, into build-asan/ (GCC, -O1), and runs them. Any sanitizer report fails the test it
# happens in, and so this script.
#   deploy/sanitize.sh [CTEST_ARGS...]   e.g. -R LiveSession
#   SANITIZE_SUITES="db_tests devices_tests" deploy/sanitize.sh   only those suites
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"

bash deploy/install-deps.sh

build_dir=${INCISE_ASAN_BUILD_DIR:-build-asan}
if [ ! -f "$build_dir/build.ninja" ]; then
  cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_FLAGS="-O1 -g -fno-omit-frame-pointer -fsanitize=address,undefined -fno-sanitize-recover=undefined" \
    -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined"
fi
read -r -a suites <<< "${SANITIZE_SUITES:-db_tests devices_tests server_tests server_integration_tests curriculum_tests sim_io_tests sim_mesh_tests}"
cmake --build "$build_dir" -j"$(nproc)" --target "${suites[@]}"  # with the binaries they NEED

# Leak checking stays on; a report aborts so that the test fails with it.
export ASAN_OPTIONS=${ASAN_OPTIONS:-abort_on_error=1:detect_stack_use_after_return=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
pattern=$(IFS='|'; echo "${suites[*]}")
cd "$build_dir"
# The suites' tests, found by their executables in ctest's listing.
tests=$(ctest -N -V 2>/dev/null | awk -v p="/bin/($pattern)\"?( |$)" '
  /^[0-9]+: Test command: / { n = $1; sub(":", "", n); if ($0 ~ p) wanted[n] = 1 }
  /^ *Test *#[0-9]+: / { n = $2; sub("#", "", n); sub(":", "", n); if (n in wanted) print $3 }')
ctest -j"$(nproc)" --output-on-failure --timeout 600 -R "^($(echo "$tests" | paste -sd'|'))\$" "$@"
