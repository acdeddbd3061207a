# Tests for sim/models/: the laws every model obeys, closed forms, hard cases.
add_executable(sim_models_tests
  models/closed_form_test.cpp
  models/hard_cases_test.cpp
  models/local_update_test.cpp
  models/model_fixtures.cpp
  models/model_laws_test.cpp
  models/projected_tangent_test.cpp
  models/rotation_extraction_test.cpp
  models/system_blocks_test.cpp
  models/tet_elements_test.cpp
)
target_link_libraries(sim_models_tests PRIVATE incise_sim GTest::gtest_main)
target_include_directories(sim_models_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})
gtest_discover_tests(sim_models_tests DISCOVERY_TIMEOUT 30)
