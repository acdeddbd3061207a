# The surgical scene runtime (sim/surgery/): tools on a tissue block, bones, events, damage.
add_executable(sim_surgery_tests
  surgery/bisection_test.cpp
  surgery/surgical_scene_test.cpp
)
target_link_libraries(sim_surgery_tests PRIVATE incise_sim_surgery GTest::gtest_main)
target_include_directories(sim_surgery_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})
gtest_discover_tests(sim_surgery_tests DISCOVERY_TIMEOUT 30)

# The liver and knee scenes (issue 6 item 8): built from the anatomy, stepped with their tools.
if(TARGET incise_sim_surgery_scenes)
  add_executable(sim_surgery_scene_tests
    surgery/scene_presets_test.cpp
    surgery/scene_file_test.cpp
    surgery/surgery_cli_test.cpp
  )
  target_link_libraries(sim_surgery_scene_tests PRIVATE incise_sim_surgery_scenes GTest::gtest_main)
  # The scene files and the CLI test (which runs the real incise binary, like cli_test.cpp).
  target_include_directories(sim_surgery_scene_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})
  target_compile_definitions(sim_surgery_scene_tests PRIVATE
    INCISE_CLI_PATH="$<TARGET_FILE:incise>"
    INCISE_SCENES_DIR="${PROJECT_SOURCE_DIR}/sim/scenes/surgery")
  add_dependencies(sim_surgery_scene_tests incise)
  gtest_discover_tests(sim_surgery_scene_tests DISCOVERY_TIMEOUT 30)
endif()

# The stability suite and benchmarks of issue 6 (docs/surgery_stability.md): random tool
# sequences on the liver and knee scenes; a CI-sized test, the long runner and the benchmark.
if(TARGET incise_sim_surgery_scenes)
  add_library(surgery_stability_suite STATIC surgery/stability_suite.cpp)
  target_link_libraries(surgery_stability_suite PUBLIC incise_sim_surgery_scenes)

  add_executable(sim_surgery_stability_tests surgery/stability_test.cpp)
  target_link_libraries(sim_surgery_stability_tests PRIVATE surgery_stability_suite
                        GTest::gtest_main)
  gtest_discover_tests(sim_surgery_stability_tests DISCOVERY_TIMEOUT 30)

  add_executable(surgery_stability surgery/stability_main.cpp)
  target_link_libraries(surgery_stability PRIVATE surgery_stability_suite)

  add_executable(bench_surgery surgery/bench_surgery.cpp)
  target_link_libraries(bench_surgery PRIVATE surgery_stability_suite)
endif()
