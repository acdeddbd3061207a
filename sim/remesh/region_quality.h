#pragma once

// What refinement reached: size, quality and length measures over the tets of a region.

#include "sim/core/types.h"
#include "sim/remesh/remesh_mesh.h"
#include "sim/remesh/size_field.h"

namespace incise::sim::remesh {

struct RegionQuality {
  int num_tets = 0;                // alive tets whose centroid is in the region
  Real max_size_ratio = 0;         // largest circumradius / target size
  Real max_radius_edge_ratio = 0;  // worst circumradius / shortest edge
  Real min_dihedral = 0;           // smallest dihedral angle [rad] (sim/mesh/mesh_quality.h)
  Real max_dihedral = 0;           // largest dihedral angle [rad]
  Real min_edge = 0;               // [m]
  Real min_altitude = 0;           // [m], the length stable_time_step uses
};

// Over the tets of the region of `field` (all zeros if there are none).
RegionQuality region_quality(const RemeshMesh& mesh, const SizeField& field);

// The shortest edge of the mesh with at least one inserted (non-original) end [m], +infinity if
// there is none: refinement keeps it >= l_min.
Real shortest_inserted_edge(const RemeshMesh& mesh);

}  // namespace incise::sim::remesh
