#pragma once

#include "sim/core/types.h"
#include "sim/mesh/boundary_surface.h"

namespace incise::sim::collide {

// The boundary faces of a tet mesh with mesh node indices: row f is
// (surface.nodes[faces(f, 0)], surface.nodes[faces(f, 1)], surface.nodes[faces(f, 2)]), same
// order and orientation. A SurfaceBvh built on these takes the mesh's deformed positions x
// directly (build(x, faces), refit(x)), with no per-step copy of the surface vertices.
// Throws std::invalid_argument if a face index is outside [0, surface.nodes.size()).
Triangles mesh_surface_faces(const BoundarySurface& surface);

}  // namespace incise::sim::collide
