# Penalty contact of tools against deformable tissue, the swept check
# against tunnelling, the haptic probe and the local force model (docs/tool_contact.md).
list(APPEND INCISE_SIM_TOOLS_SOURCES
  ${CMAKE_CURRENT_SOURCE_DIR}/force_model.cpp
  ${CMAKE_CURRENT_SOURCE_DIR}/probe.cpp
  ${CMAKE_CURRENT_SOURCE_DIR}/swept_tool_motion.cpp
  ${CMAKE_CURRENT_SOURCE_DIR}/tool_checks.cpp
  ${CMAKE_CURRENT_SOURCE_DIR}/tool_contact_response.cpp
)
