# The sanitized tests (docs/fuzzing.md, "The sanitizer build"): with INCISE_SANITIZED_TESTS=ON
# (deploy/test.sh sets it), the boundary parts (server/, db/, devices/, curriculum/, transport/,
# sim/'s parsers), their test suites, the server and agent binaries the integration tests start,
# and the fuzz targets' corpus runs are built a second time with AddressSanitizer and
# UndefinedBehaviorSanitizer, as <target>_asan. Their CTest tests are named asan/<test>.
#
# Only the boundaries are instrumented. The simulation, the renderer and the other libraries
# they link are the Release objects of the ordinary build: a second, instrumented build of the
# whole simulation (CGAL's meshing above all) would not fit in the test command's time, and the
# boundaries are where bytes from outside become values. Both instrumented and plain objects in
# one program is what ASan supports: the plain code is just not checked.
#
# -O0 -g1: instrumenting Beast's templates at -O1 doubles the compile time of the server's
# objects (measured on server/view_session.cpp, 2026-11-29: 36 s Release, 58 s with both
# sanitizers at -O0 -g1, 123 s at -O1 -g1, 180 s at -O1 -g); -g1 keeps function names and line
# numbers for the reports.
option(INCISE_SANITIZED_TESTS "Also build and test the boundaries with ASan and UBSan" OFF)
set(incise_sanitize_flags -O0 -g1 -fno-omit-frame-pointer -fsanitize=address,undefined
                          -fno-sanitize-recover=undefined)
set(incise_sanitize_link -fsanitize=address,undefined)

# incise_sanitized_map(<out-var> <values...>): the values with every target that has a sanitized
# copy replaced by that copy, as a plain name, inside $<LINK_ONLY:...> and inside $<TARGET_FILE:...>.
function(incise_sanitized_map out)
  set(mapped "")
  foreach(value IN LISTS ARGN)
    if(TARGET ${value}_asan)
      set(value ${value}_asan)
    elseif(value MATCHES "^(.*)\\$<(LINK_ONLY|TARGET_FILE):([^>]+)>(.*)$")
      if(TARGET ${CMAKE_MATCH_3}_asan)
        set(value "${CMAKE_MATCH_1}$<${CMAKE_MATCH_2}:${CMAKE_MATCH_3}_asan>${CMAKE_MATCH_4}")
      endif()
    endif()
    list(APPEND mapped "${value}")
  endforeach()
  set(${out} "${mapped}" PARENT_SCOPE)
endfunction()

# incise_sanitized_copy(<target> [SOURCES <files...>]): <target>_asan, a library or executable
# built from the same sources (or SOURCES, relative to the calling folder) with the same include
# directories and definitions, instrumented, linking the sanitized copies of the targets it links
# where they exist. Call it in the folder that defines <target>, after its dependencies' copies:
# generated sources are only visible there. Does nothing unless INCISE_SANITIZED_TESTS is on.
function(incise_sanitized_copy target)
  if(NOT INCISE_SANITIZED_TESTS)
    return()
  endif()
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "" "SOURCES")
  set(copy ${target}_asan)
  if(arg_SOURCES)
    set(sources ${arg_SOURCES})
  else()
    get_target_property(sources ${target} SOURCES)
  endif()
  get_target_property(type ${target} TYPE)
  if(type STREQUAL "EXECUTABLE")
    # Every instrumented program carries the sanitizers' default options (no environment to set).
    add_executable(${copy} ${sources} ${PROJECT_SOURCE_DIR}/tests/support/sanitizer_options.cpp)
  elseif(type STREQUAL "STATIC_LIBRARY")
    add_library(${copy} STATIC ${sources})
  else()
    message(FATAL_ERROR "incise_sanitized_copy(${target}): a ${type} cannot be copied")
  endif()
  foreach(property INCLUDE_DIRECTORIES INTERFACE_INCLUDE_DIRECTORIES COMPILE_DEFINITIONS
                   INTERFACE_COMPILE_DEFINITIONS LINK_LIBRARIES INTERFACE_LINK_LIBRARIES)
    get_target_property(values ${target} ${property})
    if(values)
      incise_sanitized_map(values ${values})
      set_property(TARGET ${copy} PROPERTY ${property} "${values}")
    endif()
  endforeach()
  get_target_property(needs ${target} MANUALLY_ADDED_DEPENDENCIES)
  if(needs)
    incise_sanitized_map(needs ${needs})
    add_dependencies(${copy} ${needs})
  endif()
  target_compile_options(${copy} PRIVATE ${incise_sanitize_flags})
  # Eigen frees what it allocates its own way, and under ASan (__SANITIZE_ADDRESS__) it stops
  # trusting malloc's 16-byte alignment and offsets its blocks by hand: a matrix made in a plain
  # object and freed in an instrumented one (or the reverse) was then freed at the wrong address.
  # Both halves allocate as the plain build does (ASan's malloc aligns to 16 bytes as well).
  target_compile_definitions(${copy} PRIVATE EIGEN_MALLOC_ALREADY_ALIGNED=1)
  target_link_options(${copy} INTERFACE ${incise_sanitize_link})
  if(type STREQUAL "EXECUTABLE")
    target_link_options(${copy} PRIVATE ${incise_sanitize_link})
  endif()
endfunction()
