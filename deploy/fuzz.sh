#!/usr/bin/env bash
# Fuzzes every boundary where bytes become values (docs/fuzzing.md): builds the fuzz targets of
# fuzz/ with clang, libFuzzer, AddressSanitizer and UndefinedBehaviorSanitizer into build-fuzz/,
# then runs each for FUZZ_SECONDS (default 600) on its seed corpus. New inputs that reach new code
# go to build-fuzz/corpus/<target>/; a crash is written to build-fuzz/crashes/<target>/ and ends
# the run with the target's name. Add a crash's input to fuzz/corpus/<target>/ once it is fixed:
# the README's test command replays every corpus.
#   deploy/fuzz.sh [TARGET...]      default: every target
#   FUZZ_SECONDS=60 deploy/fuzz.sh  a shorter run
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"

bash deploy/install-deps.sh --fuzz

build_dir=${INCISE_FUZZ_BUILD_DIR:-build-fuzz}
seconds=${FUZZ_SECONDS:-600}
if [ ! -f "$build_dir/build.ninja" ]; then
  CC=clang CXX=clang++ cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DINCISE_FUZZ=ON
fi

targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  for f in fuzz/corpus/*/; do targets+=("$(basename "$f")"); done
fi
cmake --build "$build_dir" -j"$(nproc)" --target "${targets[@]/#/fuzz_}"

export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=0:abort_on_error=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
status=0
for t in "${targets[@]}"; do
  mkdir -p "$build_dir/corpus/$t" "$build_dir/crashes/$t"
  echo "fuzz.sh: $t for $seconds s"
  # -max_len 65536 covers the API's body limit; the seeds come first, new finds after them.
  if ! "$build_dir/bin/fuzz_$t" "$build_dir/corpus/$t" "fuzz/corpus/$t" \
      -max_total_time="$seconds" -max_len=65536 -timeout=10 -rss_limit_mb=4096 \
      -artifact_prefix="$build_dir/crashes/$t/" -print_final_stats=1 \
      2> "$build_dir/$t.log"; then
    echo "fuzz.sh: $t FOUND A PROBLEM; see $build_dir/$t.log and $build_dir/crashes/$t/" >&2
    status=1
  fi
  grep -E "^stat::(number_of_executed_units|peak_rss_mb)|cov: " "$build_dir/$t.log" | tail -3
done
exit $status
