#pragma once

// Where a point of space is in the material: the affine map from the current configuration to the
// rest one of the tet the point is in (ProgressiveCutter's BladeSpace::material takes the blade
// through it). rest(p) = rest_origin + to_rest (p - origin): exact for points of that tet, the
// tet's own extension outside it (the blade's far end, above the tissue).

#include <optional>

#include "sim/core/types.h"
#include "sim/mesh/tet_mesh.h"

namespace incise::sim::cut {

struct MaterialMap {
  int tet = -1;                     // the slot the map is of
  bool inside = false;              // the point is in that tet (else the tet nearest to it)
  Vec3 origin = Vec3::Zero();       // the tet's first node, current [m]
  Vec3 rest_origin = Vec3::Zero();  // and at rest [m]
  Mat3 to_rest = Mat3::Identity();  // Dm Ds^-1

  Vec3 rest_of(const Vec3& p) const { return rest_origin + to_rest * (p - origin); }
};

// The map at p: the tet containing p (in x), or else the tet whose centroid is nearest to p within
// reach [m] of it. nullopt when there is none, or when that tet is inverted or squashed in x (its
// volume below min_volume_ratio of its rest volume: the map would mean nothing). O(#tets).
std::optional<MaterialMap> material_map_at(const TetMesh& mesh, const Vec3& p, Real reach,
                                           Real min_volume_ratio = 0.05);

// Whether some tet near the blade's edge a-b (its current bounding box, grown by reach [m], met by
// the edge) is inverted in x: the tissue there is tangled, and a blade mapped into the material
// through its neighbours would sweep material it never passed (a stroke through a tangle in the
// knee split 656 tets into 16,760, most of them inverted). A negative reach counts as 0. O(#tets).
bool tangled_near(const TetMesh& mesh, const Vec3& a, const Vec3& b, Real reach);

}  // namespace incise::sim::cut
