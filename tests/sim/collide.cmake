# Tests for sim/collide/: triangle kernels against sampling, the deformable-surface tree against a
# brute-force loop over all triangles (before and after refits and local updates) and against
# closed forms, the swept sphere, and FCL rigid bodies against closed forms.
add_executable(sim_collide_tests
  collide/collide_fixtures.cpp
  collide/rigid_body_test.cpp
  collide/surface_bvh_test.cpp
  collide/surface_bvh_closed_form_test.cpp
  collide/tool_shapes_test.cpp
  collide/triangle_geometry_test.cpp
)
target_link_libraries(sim_collide_tests PRIVATE incise_sim_collide GTest::gtest_main)
target_include_directories(sim_collide_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})
gtest_discover_tests(sim_collide_tests DISCOVERY_TIMEOUT 30)

# Benchmark: refit + sphere query on a 10k-triangle surface; prints median microseconds. Built
# with the tests, run by hand.
add_executable(bench_collide collide/bench_collide.cpp collide/collide_fixtures.cpp)
target_link_libraries(bench_collide PRIVATE incise_sim_collide)
target_include_directories(bench_collide PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})
