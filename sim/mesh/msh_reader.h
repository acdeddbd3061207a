#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "sim/mesh/tet_mesh.h"

namespace incise::sim {

// Reads a gmsh mesh, ASCII format version 2.2 or 4.1, as a TetMesh at rest.
//   nodes   all of $Nodes; node tags may be any distinct positive integers (they are mapped),
//           nodes that no tetrahedron uses are dropped (see mesh_from_file_data)
//   tets    the elements of type 4 (4-node tetrahedra) in file order; other element types
//           (points, lines, triangles, higher-order elements) are skipped
//   labels  each tet's physical tag: in 2.2 the first tag of the element, in 4.1 the first
//           physical tag of its volume entity in $Entities; 0 for a tet with none
// Tets are made positively oriented (swapping two nodes of a negative one). Other sections
// ($PhysicalNames, $Periodic, $NodeData, ...) are skipped.
// Throws MeshFileError ("FILE:LINE: problem") for a file that cannot be read, an unsupported
// version or binary file, a truncated file, counts that disagree with the records, malformed
// or non-finite numbers, a duplicate node tag, a tet referring to a node not in $Nodes, a tet
// that repeats a node or has zero volume, or a file without tetrahedra.
TetMesh read_msh(const std::filesystem::path& path);

// The same for the text of a .msh file; name stands for the file in error messages.
TetMesh read_msh_string(std::string_view text, const std::string& name = "<msh>");

}  // namespace incise::sim
