# Mesh files and quality (sim/mesh readers, writers, mesh_quality) and `incise mesh-info`, which
# the CLI test runs as the real binary.
add_executable(sim_mesh_io_tests
  ${CMAKE_CURRENT_SOURCE_DIR}/mesh_io/mesh_info_cli_test.cpp
  ${CMAKE_CURRENT_SOURCE_DIR}/mesh_io/mesh_quality_test.cpp
  ${CMAKE_CURRENT_SOURCE_DIR}/mesh_io/msh_reader_test.cpp
  ${CMAKE_CURRENT_SOURCE_DIR}/mesh_io/round_trip_test.cpp
  ${CMAKE_CURRENT_SOURCE_DIR}/mesh_io/tetgen_reader_test.cpp
  ${CMAKE_CURRENT_SOURCE_DIR}/mesh_io/vtu_writer_test.cpp
)
target_link_libraries(sim_mesh_io_tests PRIVATE incise_sim GTest::gtest_main)
target_include_directories(sim_mesh_io_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})
target_compile_definitions(sim_mesh_io_tests PRIVATE INCISE_CLI_PATH="$<TARGET_FILE:incise>")
add_dependencies(sim_mesh_io_tests incise)
gtest_discover_tests(sim_mesh_io_tests DISCOVERY_TIMEOUT 30)
