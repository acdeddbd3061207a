#pragma once

// The surface a scalpel's blade sweeps, as a triangle soup in the CURRENT (deformed) configuration:
// the cut is made where the trainee sees the tissue, not where it rests. The blade is its cutting
// edge, a segment (a, b); moving from pose (a0, b0) to pose (a1, b1) in one step it sweeps the
// bilinear quad a0 b0 b1 a1, approximated here by the two triangles (a0, b0, b1) and (a0, b1, a1).

#include <vector>

#include "sim/core/types.h"

namespace incise::sim::cut {

struct CutSurface {
  Points vertices;      // #V by 3 [m], current configuration
  Triangles triangles;  // #T by 3 indices into vertices
};

// The two triangles swept by the blade edge moving from (a0, b0) to (a1, b1) [m].
// Throws std::invalid_argument if a0 == b0 or a1 == b1 (a blade of zero length).
CutSurface blade_sweep(const Vec3& a0, const Vec3& b0, const Vec3& a1, const Vec3& b1);

// The strip swept by a path of blade poses: pose k is the blade edge (a.row(k), b.row(k)) [m];
// each consecutive pair of poses sweeps a quad as in blade_sweep, so a path that turns or twists
// gives a non-planar surface of 2 (#poses - 1) triangles.
// Throws std::invalid_argument if a and b differ in size, there are fewer than 2 poses or a pose
// has a blade of zero length.
CutSurface blade_path(const Points& a, const Points& b);

// The parameters t in [0, 1] at which the segment p + t (q - p) meets the surface, sorted, with
// hits closer than 1e-9 in t merged (a segment through the diagonal shared by two triangles hits
// both). Points on a triangle's border count (a relative tolerance of 1e-12), a segment parallel
// to a triangle's plane does not meet it. Appends nothing for a zero-length segment. Clears hits.
void segment_hits(const CutSurface& surface, const Vec3& p, const Vec3& q, std::vector<Real>& hits);

// The distance [m] from point to the nearest triangle of surface (infinity if it has none).
Real distance_to_surface(const CutSurface& surface, const Vec3& point);

// The axis-aligned bounding box of the surface's vertices.
Box3 surface_bounds(const CutSurface& surface);

}  // namespace incise::sim::cut
