# Benchmarks of issue 4 (tests/sim/bench/): built with the tests, run by hand, not registered with
# ctest (they measure, they do not assert).
#   bench_accuracy  speed against error: every model x integrator on the block-compression and
#                   cantilever scenes at several resolutions; CSV, SVG plots and a table
#   bench_models    Google Benchmark: per-tet model kernels and one implicit Euler step
add_executable(bench_accuracy
  bench/accuracy_main.cpp
  bench/accuracy_scenes.cpp
  bench/reference_solve.cpp
  bench/svg_plot.cpp
)
target_link_libraries(bench_accuracy PRIVATE incise_sim)
target_include_directories(bench_accuracy PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})

find_package(benchmark REQUIRED)
add_executable(bench_models bench/bench_models.cpp)
target_link_libraries(bench_models PRIVATE incise_sim benchmark::benchmark)
