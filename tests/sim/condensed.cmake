# Tests of the hybrid condensed model (sim/models/hybrid_condensed_model.h), and its benchmark.
add_executable(sim_condensed_tests condensed/hybrid_condensed_model_test.cpp)
target_link_libraries(sim_condensed_tests PRIVATE incise_sim GTest::gtest_main)
gtest_discover_tests(sim_condensed_tests DISCOVERY_TIMEOUT 30)

# Force evaluation cost, hybrid against the full model: run by hand (it measures, not asserts).
add_executable(bench_condensed condensed/bench_condensed.cpp)
target_link_libraries(bench_condensed PRIVATE incise_sim)
