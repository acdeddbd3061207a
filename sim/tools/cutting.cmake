# What the scalpel's hand feels: the blade's depth in the tissue and the tissue's cutting
# resistance (docs/cutting.md, "What the hand feels").
list(APPEND INCISE_SIM_TOOLS_SOURCES
  ${CMAKE_CURRENT_SOURCE_DIR}/blade_in_tissue.cpp
  ${CMAKE_CURRENT_SOURCE_DIR}/cutting_resistance.cpp
)
