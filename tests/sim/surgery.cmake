# The surgical scene runtime (sim/surgery/): tools on a tissue block, bones, events, damage.
add_executable(sim_surgery_tests
  surgery/surgical_scene_test.cpp
)
target_link_libraries(sim_surgery_tests PRIVATE incise_sim_surgery GTest::gtest_main)
target_include_directories(sim_surgery_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})
gtest_discover_tests(sim_surgery_tests DISCOVERY_TIMEOUT 30)

# The liver and knee scenes (issue 6 item 8): built from the anatomy, stepped with their tools.
if(TARGET incise_sim_surgery_scenes)
  add_executable(sim_surgery_scene_tests surgery/scene_presets_test.cpp)
  target_link_libraries(sim_surgery_scene_tests PRIVATE incise_sim_surgery_scenes GTest::gtest_main)
  gtest_discover_tests(sim_surgery_scene_tests DISCOVERY_TIMEOUT 30)
endif()
