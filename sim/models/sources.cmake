# Model sources (paths relative to sim/), added to incise_sim by sim/CMakeLists.txt.
set(INCISE_SIM_MODELS_SOURCES ${INCISE_SIM_MODELS_SOURCES}
  models/corotational_batch.cpp
  models/corotational_fem.cpp
  models/hybrid_condensed_model.cpp
  models/hybrid_condensed_partition.cpp
  models/hybrid_condensed_schur_complement.cpp
  models/hybrid_condensed_topology.cpp
  models/linear_fem.cpp
  models/model.cpp
  models/mass_spring_model.cpp
  models/neo_hookean_fem.cpp
  models/nodal_pressure_fem.cpp
  models/rotation_extraction.cpp
  models/stvk_fem.cpp
  models/tet_elements.cpp
)
