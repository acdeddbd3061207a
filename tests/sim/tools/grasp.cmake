# Tests for the grasper (sim/tools/grasper.h): tearing at the threshold against a static solve,
# rigid following of the jaws, opening, empty grasps, grasping after refinement (an AdaptiveBody,
# hence incise_sim_remesh for this executable only), Newton's third law and momentum, bad input.
add_executable(sim_tools_grasp_tests
  tools/grasp_fixtures.cpp
  tools/grasp_hold_test.cpp
  tools/grasp_input_test.cpp
  tools/grasp_refine_test.cpp
  tools/grasp_release_test.cpp
)
target_link_libraries(sim_tools_grasp_tests PRIVATE incise_sim_tools incise_sim_remesh
                      GTest::gtest_main)
target_include_directories(sim_tools_grasp_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})
gtest_discover_tests(sim_tools_grasp_tests DISCOVERY_TIMEOUT 30)
