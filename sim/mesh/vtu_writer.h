#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "sim/core/types.h"
#include "sim/mesh/tet_mesh.h"

namespace incise::sim {

// Further fields for a .vtu file beside the ones every file has.
struct VtuFields {
  // (name, #nodes by 3 values), e.g. ("velocity", mesh.v) or ("force", f)
  std::vector<std::pair<std::string, Points>> node_vectors;
  // (name, #tets values), e.g. ("von_mises", stress [Pa])
  std::vector<std::pair<std::string, VecX>> tet_scalars;
};

// The VTK XML UnstructuredGrid (.vtu, ASCII) text of mesh for ParaView:
//   Points     the current positions mesh.x [m]
//   Cells      the tets as VTK_TETRA (type 10, same node order: VTK's tetra is positively
//              oriented in the same sense as TetMesh)
//   PointData  "displacement" = x - rest [m] (the active vectors, for Warp By Vector), then
//              extra.node_vectors in order
//   CellData   "label" (Int32; the active scalars), then extra.tet_scalars in order
// Numbers are written in their shortest exact form.
// Throws std::invalid_argument if a field has the wrong number of rows, a name is empty, not
// made of letters, digits, '_', '-' and '.', or repeats another (including "displacement" and
// "label"), or a position or field value is not finite (VTK's ASCII reader cannot read one).
std::string format_vtu(const TetMesh& mesh, const VtuFields& extra = {});

// Writes format_vtu(mesh, extra) to path; throws like format_vtu, or MeshFileError if the file
// cannot be written.
void write_vtu(const std::filesystem::path& path, const TetMesh& mesh, const VtuFields& extra = {});

}  // namespace incise::sim
