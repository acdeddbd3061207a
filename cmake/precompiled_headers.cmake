# Precompiled headers for the targets whose objects spend most of their time parsing the same
# third-party headers. Measured on a clean build (2 cores, 2026-11-28, ninja's log and depfiles):
# Eigen takes about 2.5 s to parse per object, GoogleTest 2.5 s, nlohmann-json 3 s and Beast with
# Asio 6.5 s, so an object of server_tests spent about 13 of its 13.5 s in headers, and parsing was
# about half of the whole build's compile time. Each target below precompiles once what most of its
# objects include; a target with one or two objects gains nothing and is left out.
#
# The headers only save time: every source still includes what it uses, so removing a target from
# this list (or the whole file) changes no meaning.

# incise_precompile(<target> [EIGEN] [SPARSE] [GTEST] [JSON] [BEAST] [WEBSOCKET])
#   EIGEN: Eigen's dense core and geometry; SPARSE: Eigen's sparse module; GTEST: GoogleTest;
#   JSON: nlohmann-json; BEAST: Asio and Beast's core and HTTP (the target must link incise_asio,
#   whose definitions the headers need); WEBSOCKET: Beast's WebSocket stream as well.
function(incise_precompile target)
  cmake_parse_arguments(PARSE_ARGV 1 arg "EIGEN;SPARSE;GTEST;JSON;BEAST;WEBSOCKET" "" "")
  if(arg_UNPARSED_ARGUMENTS OR NOT TARGET ${target})
    message(FATAL_ERROR "incise_precompile(${target}): no such target or unknown arguments "
                        "'${arg_UNPARSED_ARGUMENTS}'")
  endif()
  set(headers <algorithm> <string> <vector>)
  if(arg_EIGEN OR arg_SPARSE)
    list(APPEND headers <Eigen/Core> <Eigen/Geometry>)
  endif()
  if(arg_SPARSE)
    list(APPEND headers <Eigen/Sparse>)
  endif()
  if(arg_GTEST)
    list(APPEND headers <gtest/gtest.h>)
  endif()
  if(arg_JSON)
    list(APPEND headers <nlohmann/json.hpp>)
  endif()
  if(arg_BEAST OR arg_WEBSOCKET)
    list(APPEND headers <boost/asio/io_context.hpp> <boost/asio/ip/tcp.hpp>
         <boost/beast/core.hpp> <boost/beast/http.hpp>)
  endif()
  if(arg_WEBSOCKET)
    list(APPEND headers <boost/beast/websocket.hpp>)
  endif()
  target_precompile_headers(${target} PRIVATE ${headers})
  if(TARGET ${target}_asan)  # its sanitized copy (cmake/sanitized.cmake) parses the same
    target_precompile_headers(${target}_asan PRIVATE ${headers})
  endif()
endfunction()

# The product's libraries.
incise_precompile(incise_sim SPARSE)
incise_precompile(incise_sim_io EIGEN JSON)
incise_precompile(incise_sim_remesh EIGEN)
incise_precompile(incise_sim_tools EIGEN)
incise_precompile(incise_sim_cut EIGEN)
incise_precompile(incise_sim_collide EIGEN)
incise_precompile(incise_sim_surgery SPARSE)
incise_precompile(incise_sim_surgery_scenes SPARSE JSON)
incise_precompile(incise_render EIGEN)
incise_precompile(incise SPARSE JSON)
incise_precompile(incise_devices_protocol EIGEN JSON)
incise_precompile(incise_agent BEAST WEBSOCKET)
incise_precompile(incise_server SPARSE JSON BEAST)

# The test suites and their support.
incise_precompile(incise_test_support JSON WEBSOCKET)
incise_precompile(sim_models_tests GTEST SPARSE)
incise_precompile(sim_solve_tests GTEST SPARSE)
incise_precompile(sim_surgery_tests GTEST SPARSE JSON)
incise_precompile(sim_mesh_tests GTEST EIGEN)
incise_precompile(sim_mesh_cgal_tests GTEST EIGEN)
incise_precompile(sim_render_tests GTEST EIGEN)
incise_precompile(sim_remesh_tests GTEST EIGEN)
incise_precompile(sim_cut_tests GTEST EIGEN)
incise_precompile(sim_collide_tests GTEST EIGEN)
incise_precompile(sim_cli_tests GTEST EIGEN JSON)
incise_precompile(sim_scene_tests GTEST EIGEN)
incise_precompile(sim_hard_cases_tests GTEST SPARSE)
incise_precompile(sim_tools_contact_tests GTEST SPARSE)
incise_precompile(sim_tools_damage_tests GTEST EIGEN)
incise_precompile(sim_tools_grasp_tests GTEST SPARSE)
incise_precompile(devices_tests GTEST)
incise_precompile(curriculum_tests GTEST JSON)
incise_precompile(db_tests GTEST)
incise_precompile(server_tests GTEST SPARSE JSON BEAST)
incise_precompile(server_integration_tests GTEST JSON WEBSOCKET)
