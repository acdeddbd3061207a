# Mesh files and quality: readers, writers, quality measures. Paths relative to sim/.
set(INCISE_SIM_MESH_SOURCES ${INCISE_SIM_MESH_SOURCES}
  mesh/mesh_from_file_data.cpp
  mesh/mesh_info.cpp
  mesh/mesh_quality.cpp
  mesh/mesh_text_reader.cpp
  mesh/mesh_text_writer.cpp
  mesh/msh_reader.cpp
  mesh/msh_writer.cpp
  mesh/read_mesh_file.cpp
  mesh/tetgen_reader.cpp
  mesh/tetgen_writer.cpp
  mesh/vtu_writer.cpp
)
