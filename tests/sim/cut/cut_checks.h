#pragma once

// Invariants of a cut mesh, shared by the cutting tests: orientation, conformity, a closed and
// manifold boundary, connected components and the crack faces' place on the blade's surface.

#include <string>
#include <vector>

#include "sim/core/types.h"
#include "sim/cut/cut_mesh.h"
#include "sim/cut/cut_surface.h"
#include "sim/mesh/tet_mesh.h"

namespace incise::sim::cut::testing {

// The blade sweep of a square of half side `half` [m] in the plane through point with normal
// (not necessarily unit): two triangles covering the square.
CutSurface plane_blade(const Vec3& point, const Vec3& normal, Real half);

// "" if every interior face is shared by exactly two tets and the boundary faces form a closed,
// consistently oriented, manifold surface (each directed boundary edge once, its reverse once;
// the faces around each boundary vertex form a single fan); else what is wrong.
std::string boundary_problem(const Tets& tets);

// Component index per tet, tets connected through shared faces; count in *num_components.
std::vector<int> tet_components(const Tets& tets, int* num_components);

// Total area [m^2] of the boundary faces at points.
Real boundary_area(const Points& points, const Tets& tets);

// Total area [m^2] of triangles at points.
Real triangles_area(const Points& points, const Triangles& triangles);

// The smallest signed tet volume [m^3] at points.
Real min_volume(const Points& points, const Tets& tets);

// A box mesh with every interior node moved by up to `jitter` times the cell size, in a fixed
// pseudo-random way (seeded); boundary nodes stay, so the box's volume is unchanged.
TetMesh jittered_box(const Vec3& size, const Vec3i& cells, Real jitter, unsigned seed);

// Checks every invariant after a cut of `before` along surface into `after` (gtest assertions):
// positive rest (and current) orientation, rest volume kept to 1e-9 relative, a conforming mesh
// with a closed manifold boundary, boundary area grown by exactly the crack faces' area, crack
// face nodes on the surface (current configuration) within 1e-9, or within snap times the
// longest edge for a node snapped there, every tet's label that of the tet of `before` holding its
// rest centroid, and every changed tet slot reported in report.changed_tets.
void expect_cut_invariants(const TetMesh& before, const TetMesh& after, const CutReport& report,
                           const CutSurface& surface, Real snap);

}  // namespace incise::sim::cut::testing
