#pragma once
// The mesh a scene asks for, for the CLI: mesh.box (make_box_mesh), mesh.file (a gmsh or TetGen
// file, relative to the scene's folder), mesh.generate (CGAL Mesh_3 through
// sim/mesh/cgal/mesh_generation.h) or mesh.segmentation (a NIfTI volume meshed the same way). Kept
// out of sim/scene so that the core needs no files or CGAL.
#include <filesystem>

#include "sim/mesh/cgal/mesh_generation.h"
#include "sim/mesh/tet_mesh.h"
#include "sim/scene/scene.h"

namespace incise::sim {

// Throws SceneError("mesh.file", "<file>:<line>: <problem>") for a bad file,
// SceneError("mesh.segmentation.file", "<file>: <problem>") for a bad volume, and
// SceneError("mesh.generate" or "mesh.segmentation", ...) when generation fails.
TetMesh build_scene_mesh(const Scene& scene, const std::filesystem::path& scene_dir);

// The Mesh_3 criteria for a segmentation at cell_size [m] (the largest tet and surface triangle):
// the surface follows the voxels to a quarter cell, but never closer than one voxel.
MeshingCriteria segmentation_criteria(const LabelVolume& volume, Real cell_size);

}  // namespace incise::sim
