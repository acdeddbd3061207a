# Tests for sim/cut/: the cases of one cut tet, and cuts of box meshes checked against every
# invariant (orientation, volume, conformity, a closed manifold boundary, the crack on the blade's
# surface, labels) and against the closed-form volumes of a box cut by planes; progressive cuts
# frame by frame with the temporary subdivision of the tets the blade is inside.
add_executable(sim_cutting_tests
  cutting/cut_checks.cpp
  cutting/cut_mesh_test.cpp
  cutting/material_map_test.cpp
  cutting/progressive_cutter_test.cpp
  cutting/simplify_cut_test.cpp
  cutting/tet_split_test.cpp
)
target_link_libraries(sim_cutting_tests PRIVATE incise_sim_cut GTest::gtest_main)
target_include_directories(sim_cutting_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})
gtest_discover_tests(sim_cutting_tests DISCOVERY_TIMEOUT 30)

# Benchmark (not a test): per-frame update time of a progressive cut across a ~5k-tet block.
add_executable(bench_cut cutting/bench_cut.cpp)
target_link_libraries(bench_cut PRIVATE incise_sim_cut)
