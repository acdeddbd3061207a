# Tests for the damage metrics (sim/tools/damage_*.h): the strain kernel against closed forms,
# strain tracking on a uniformly stretched box, cuts against the marked target with real cuts
# (hence incise_sim_cut, for this executable only), contacts with protected structures, the
# metric rows, bad input.
add_executable(sim_tools_damage_tests
  tools/damage_allocation_test.cpp
  tools/damage_contact_test.cpp
  tools/damage_cut_test.cpp
  tools/damage_input_test.cpp
  tools/damage_strain_test.cpp
  tools/damage_strain_tracking_test.cpp
)
target_link_libraries(sim_tools_damage_tests PRIVATE incise_sim_tools incise_sim_cut
                      GTest::gtest_main)
gtest_discover_tests(sim_tools_damage_tests DISCOVERY_TIMEOUT 30)
