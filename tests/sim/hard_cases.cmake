# Issue 4 at the scene level (sim/scene/scene_run.h): a clamped beam converging to beam theory as
# the mesh refines, and the hard cases (a node yanked far away, nu = 0.499, slivers, a step at 10x
# the explicit limit, an inverted tet, a million steps at rest), every one finite and, where
# released, back at its rest shape; a run that blows up stops and says so (divergence_test).
add_executable(sim_hard_cases_tests
  hard_cases/beam_convergence_test.cpp
  hard_cases/release_test.cpp
  hard_cases/difficult_inputs_test.cpp
  hard_cases/divergence_test.cpp
)
target_link_libraries(sim_hard_cases_tests PRIVATE incise_sim GTest::gtest_main)
target_include_directories(sim_hard_cases_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})
gtest_discover_tests(sim_hard_cases_tests DISCOVERY_TIMEOUT 30 PROPERTIES TIMEOUT 300)
