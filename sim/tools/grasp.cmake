# The grasper: holds tissue vertices to the jaws, measures the pull, releases on
# opening or tearing (docs/grasping.md).
list(APPEND INCISE_SIM_TOOLS_SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/grasper.cpp)
