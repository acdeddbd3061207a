# Damage metrics: strain over tissue thresholds, cuts against the marked target,
# contacts with protected structures; per-element state and a session snapshot for scoring.
list(APPEND INCISE_SIM_TOOLS_SOURCES
  ${CMAKE_CURRENT_SOURCE_DIR}/damage_helpers.cpp
  ${CMAKE_CURRENT_SOURCE_DIR}/damage_metrics.cpp
  ${CMAKE_CURRENT_SOURCE_DIR}/damage_strain.cpp
  ${CMAKE_CURRENT_SOURCE_DIR}/damage_target.cpp
  ${CMAKE_CURRENT_SOURCE_DIR}/damage_tracker.cpp
  ${CMAKE_CURRENT_SOURCE_DIR}/damage_tracker_cut.cpp
)
