#pragma once
// The mesh a scene asks for, for the CLI: mesh.box (make_box_mesh), mesh.file (a gmsh or TetGen
// file, relative to the scene's folder) or mesh.generate (CGAL Mesh_3 through
// sim/mesh/cgal/mesh_generation.h). Kept out of sim/scene so that the core needs no files or CGAL.
#include <filesystem>

#include "sim/mesh/tet_mesh.h"
#include "sim/scene/scene.h"

namespace incise::sim {

// Throws SceneError("mesh.file", "<file>:<line>: <problem>") for a bad file and
// SceneError("mesh.generate", ...) when generation fails.
TetMesh build_scene_mesh(const Scene& scene, const std::filesystem::path& scene_dir);

}  // namespace incise::sim
