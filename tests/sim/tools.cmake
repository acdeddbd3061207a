# Tests of sim/tools/, one executable per part (tests/sim/tools/<part>.cmake).
foreach(part contact grasp damage)
  if(EXISTS ${CMAKE_CURRENT_SOURCE_DIR}/tools/${part}.cmake)
    include(${CMAKE_CURRENT_SOURCE_DIR}/tools/${part}.cmake)
  endif()
endforeach()
