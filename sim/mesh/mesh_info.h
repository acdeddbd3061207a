#pragma once

#include <ostream>

#include "sim/mesh/tet_mesh.h"

namespace incise::sim {

// Writes a human-readable report of mesh at rest (mesh.rest), one "key: value" line each:
// node and tet counts, tets per label, bounding box, total volume, and the quality summary
// (summarize_quality: volume, aspect ratio and dihedral angle ranges, inverted and degenerate
// counts, histograms). What `incise mesh-info FILE` prints.
void print_mesh_info(const TetMesh& mesh, std::ostream& out);

}  // namespace incise::sim
