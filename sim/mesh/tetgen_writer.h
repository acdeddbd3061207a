#pragma once

#include <filesystem>
#include <string>

#include "sim/mesh/tet_mesh.h"

namespace incise::sim {

// The TetGen .node text of mesh at rest (mesh.rest), numbered from 1, without attributes or
// markers, numbers in their shortest exact form.
std::string format_tetgen_node(const TetMesh& mesh);

// The TetGen .ele text of mesh, numbered from 1, 4 nodes per tet and one attribute, the label
// (TetGen's region attribute), so that read_tetgen gives back the same tets and labels.
// Throws std::invalid_argument for a negative label.
std::string format_tetgen_ele(const TetMesh& mesh);

// Writes base.node and base.ele (base as read_tetgen takes it; a .node or .ele extension is
// replaced). Throws MeshFileError if a file cannot be written.
void write_tetgen(const std::filesystem::path& base, const TetMesh& mesh);

}  // namespace incise::sim
