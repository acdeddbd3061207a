# Tests of the active region (sim/solve/active_region.h): bookkeeping, exactness of the sub-model's
# forces, a poke against the full simulation, waking under load.
add_executable(sim_active_region_tests
  active_region/active_region_test.cpp
  active_region/active_stepper_test.cpp
  active_region/poke_fixture.cpp
)
target_link_libraries(sim_active_region_tests PRIVATE incise_sim GTest::gtest_main)
gtest_discover_tests(sim_active_region_tests DISCOVERY_TIMEOUT 30)

# Benchmark: steps/s with and without the active region; built with the tests, run by hand.
add_executable(bench_active_region active_region/bench_active_region.cpp
                                   active_region/poke_fixture.cpp)
target_link_libraries(bench_active_region PRIVATE incise_sim)

# Issue 5's liver benchmark: a CGAL liver-like organ probed by a scripted tool, full against
# active region; run by hand or from deploy/bench.sh.
add_executable(bench_liver active_region/bench_liver.cpp active_region/poke_fixture.cpp)
target_link_libraries(bench_liver PRIVATE incise_sim incise_sim_cgal)
