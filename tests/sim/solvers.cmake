# Tests of sim/solve/ beyond symplectic Euler, with their own small models (tests/sim/solvers/
# test_models.h) so that they do not depend on sim/models/.
add_executable(sim_solvers_tests
  solvers/adaptive_explicit_test.cpp
  solvers/block_sparse_test.cpp
  solvers/central_difference_test.cpp
  solvers/constrained_system_test.cpp
  solvers/implicit_euler_test.cpp
  solvers/preconditioner_test.cpp
  solvers/stable_time_step_test.cpp
  solvers/static_solver_test.cpp
  solvers/test_models.cpp
)
target_link_libraries(sim_solvers_tests PRIVATE incise_sim GTest::gtest_main)
gtest_discover_tests(sim_solvers_tests DISCOVERY_TIMEOUT 30)
