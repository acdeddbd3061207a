#pragma once

#include <filesystem>

#include "sim/mesh/tet_mesh.h"

namespace incise::sim {

// Reads a tet mesh file by its name: ".msh" with read_msh; ".node" or ".ele" with read_tetgen;
// any other name as a TetGen base name if name.node exists.
// Throws MeshFileError (no line) for a name that is none of these, else as the reader does.
TetMesh read_mesh_file(const std::filesystem::path& path);

}  // namespace incise::sim
