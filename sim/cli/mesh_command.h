#pragma once

#include <ostream>
#include <string>
#include <vector>

namespace incise::sim {

// `incise mesh VOLUME.nii[.gz] --labels 1=NAME,2=NAME --cell-size H --out MESH`: meshes a
// labelled segmentation volume (sim/mesh/nifti/nifti_segmentation.h) with CGAL Mesh_3 at cells
// of H metres, each tet labelled with the label value it lies in, in the volume's world
// coordinates (its affine kept, in metres), and writes MESH by its extension: .msh (gmsh 4.1),
// .vtu (ParaView) or .node (TetGen .node/.ele). Prints the volume (voxels, spacing, axes, origin),
// each tissue's voxel and meshed volumes, and the mesh's quality (print_mesh_info: counts,
// dihedral angles, aspect ratios).
//   args  the arguments after "incise", starting with "mesh"
// Returns kExitOk; kExitUsage with one line on err for bad arguments, a bad volume (the reader's
// message: unknown or empty labels, wrong dimensions, a truncated file, ...) or an unwritable
// MESH; kExitFailed if CGAL fails.
int run_mesh_command(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

}  // namespace incise::sim
