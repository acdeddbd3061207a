# The surgical scene runtime (sim/surgery/): tools on a tissue block, bones, events, damage.
add_executable(sim_surgery_tests
  surgery/surgical_scene_test.cpp
)
target_link_libraries(sim_surgery_tests PRIVATE incise_sim_surgery GTest::gtest_main)
target_include_directories(sim_surgery_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})
gtest_discover_tests(sim_surgery_tests DISCOVERY_TIMEOUT 30)
