#pragma once

#include <filesystem>
#include <string>

#include "sim/mesh/tet_mesh.h"

namespace incise::sim {

enum class MshVersion { k2_2, k4_1 };

// The gmsh ASCII text of mesh at rest (mesh.rest), in format 2.2 or 4.1, such that read_msh
// gives back the same nodes, tets and labels in the same order (numbers are written in their
// shortest exact form). Node and element tags are 1, 2, ...; a tet's label is its physical tag,
// label 0 meaning none (2.2 writes physical tag 0, 4.1 a volume without physical tag). 4.1
// puts each run of consecutive tets with the same label in an element block of its own volume
// entity (one volume per distinct label), which keeps the tets' order.
// Throws std::invalid_argument for a negative label (gmsh physical tags are positive).
std::string format_msh(const TetMesh& mesh, MshVersion version);

// Writes format_msh(mesh, version) to path; throws MeshFileError if the file cannot be written.
void write_msh(const std::filesystem::path& path, const TetMesh& mesh, MshVersion version);

}  // namespace incise::sim
