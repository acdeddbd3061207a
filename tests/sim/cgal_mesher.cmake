# Tests for sim/mesh/cgal/ (CGAL Mesh_3 behind one door), mirroring its files.
if(TARGET incise_sim_cgal)
  add_executable(sim_cgal_mesher_tests
    cgal_mesher/implicit_shape_test.cpp
    cgal_mesher/label_volume_test.cpp
    cgal_mesher/mesh_checks.cpp
    cgal_mesher/mesh_generation_test.cpp
    cgal_mesher/mesh_labelled_volume_test.cpp
    cgal_mesher/anatomy_test.cpp
  )
  target_link_libraries(sim_cgal_mesher_tests PRIVATE incise_sim_cgal GTest::gtest_main)
  gtest_discover_tests(sim_cgal_mesher_tests DISCOVERY_TIMEOUT 30)
endif()
