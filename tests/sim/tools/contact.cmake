# Tests of the tools' contact response, the swept check, the probe and the haptic force model
# (sim/tools/contact.cmake, docs/tool_contact.md), and the contact benchmark (run by hand).
add_executable(sim_tools_contact_tests
  tools/contact_fixtures.cpp
  tools/contact_force_model_test.cpp
  tools/contact_probe_test.cpp
  tools/contact_response_test.cpp
  tools/contact_stability_test.cpp
  tools/contact_static_test.cpp
  tools/contact_tunnelling_test.cpp
)
target_link_libraries(sim_tools_contact_tests PRIVATE incise_sim_tools GTest::gtest_main)
target_include_directories(sim_tools_contact_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})
gtest_discover_tests(sim_tools_contact_tests DISCOVERY_TIMEOUT 30)

# Benchmark: built with the tests, run by hand (it measures, it does not assert).
add_executable(bench_tool_contact tools/contact_bench.cpp)
target_link_libraries(bench_tool_contact PRIVATE incise_sim_tools)
