#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "sim/mesh/tet_mesh.h"

namespace incise::sim {

// Reads a TetGen mesh (a .node and a .ele file) as a TetMesh at rest.
//   node_or_ele_or_base  "mesh.node", "mesh.ele" or the base "mesh" (also "mesh.1" as TetGen
//                        names its output): the other file has the same base
// .node: "#points 3 #attributes #markers(0|1)", then "index x y z [attributes] [marker]" per
// point; point attributes and markers are ignored. The first point's index (0 or 1) sets the
// numbering of both files, and points must be numbered consecutively from it.
// .ele: "#tets #nodes-per-tet(4|10) #attributes", then "index n1 n2 n3 n4 [...] [attributes]";
// of a 10-node tet only the 4 corners (listed first) are used. With attributes, the first (the
// region attribute of `tetgen -A`) is the tet's label and must be a non-negative integer value;
// without, labels are 0. '#' starts a comment. Tets are made positively oriented and unused
// nodes dropped, as for read_msh (see mesh_from_file_data).
// Throws MeshFileError ("FILE:LINE: problem", FILE the .node or the .ele) like read_msh:
// missing file, truncation, bad counts, bad or out-of-range indices, non-finite coordinates,
// repeated nodes or zero volume in a tet.
TetMesh read_tetgen(const std::filesystem::path& node_or_ele_or_base);

// The same for the texts of the two files; the names stand for them in error messages.
TetMesh read_tetgen_strings(std::string_view node_text, std::string_view ele_text,
                            const std::string& node_name = "<node>",
                            const std::string& ele_name = "<ele>");

// The .node and .ele paths of a TetGen mesh named as read_tetgen takes it.
std::filesystem::path tetgen_node_path(const std::filesystem::path& node_or_ele_or_base);
std::filesystem::path tetgen_ele_path(const std::filesystem::path& node_or_ele_or_base);

}  // namespace incise::sim
