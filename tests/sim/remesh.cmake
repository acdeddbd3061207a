# Tests for sim/remesh/: predicates, the mutable mesh, flips, insertion and removal sequences
# checked against every invariant after each operation, and exact restoration by decimation.
add_executable(sim_remesh_tests
  remesh/predicates_test.cpp
  remesh/remesh_fixtures.cpp
  remesh/remesh_mesh_test.cpp
  remesh/remesh_sequence_test.cpp
  # Drivers: size and quality control, decimation, state transfer, the time-step floor.
  remesh/decimation_test.cpp
  remesh/refinement_test.cpp
  remesh/state_transfer_test.cpp
  remesh/adaptation_regions_test.cpp
  # The adaptive body: conservation, rest, no popping, round trip (models from make_model).
  remesh/adaptive_body_test.cpp
  # A scene's "adaptivity": the adaptive runner against the fixed-mesh one.
  remesh/adaptive_run_test.cpp
)
target_link_libraries(sim_remesh_tests PRIVATE incise_sim_remesh GTest::gtest_main)
target_include_directories(sim_remesh_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})
gtest_discover_tests(sim_remesh_tests DISCOVERY_TIMEOUT 30)

# Benchmark: cost per insertion and per removal; built with the tests, run by hand.
add_executable(bench_remesh remesh/bench_remesh.cpp remesh/remesh_fixtures.cpp)
target_link_libraries(bench_remesh PRIVATE incise_sim_remesh)
target_include_directories(bench_remesh PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})

# Benchmark: a refinement pass around a 1 cm tool region on a 7,200-tet box and its decimation.
add_executable(bench_refinement remesh/bench_refinement.cpp)
target_link_libraries(bench_refinement PRIVATE incise_sim_remesh)

# Benchmark: seed 000's probing experiment (its Figure 6): low-resolution, high-resolution and
# adaptive mass-spring blocks probed by a sliding sphere; writes results/probing.csv.
add_executable(bench_probing remesh/bench_probing.cpp bench/svg_plot.cpp)
target_link_libraries(bench_probing PRIVATE incise_sim_remesh)
target_include_directories(bench_probing PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})

# Benchmark: per insertion, per removal and whole-pass cost through AdaptiveBody on a CGAL
# liver-like organ, full scan against the region walk of RefinementSettings::region (issue 5).
if(TARGET incise_sim_cgal)
  add_executable(bench_remesh_pass remesh/bench_remesh_pass.cpp)
  target_link_libraries(bench_remesh_pass PRIVATE incise_sim_remesh incise_sim_cgal)
  # Benchmark: the liver stroked by a load, fine / active region / coarse / adaptive, steps per
  # second and error in the probed region against the fine mesh (issue 5).
  add_executable(bench_liver_adaptive remesh/bench_liver_adaptive.cpp)
  target_link_libraries(bench_liver_adaptive PRIVATE incise_sim_remesh incise_sim_cgal)
endif()
