#pragma once

// The temporary subdivision of the tets the blade is inside (Knee Arthroscopy VR, section VII.B.2,
// "subdivide a tetrahedron temporarily until it is completely cut", Fig. 17), so that the trainee
// sees the crack up to the blade before the blade leaves the tet.
//
// The blade's cutting edge (a, b) crosses a front tet along a chord. The crack inside that tet is
// the part of the swept surface behind the chord: a polygon whose corners are the surface's
// crossings with the tet's edges (or its nodes on the surface, after snapping) and the points
// where the chord pierces the tet's faces. Each front tet is split as a star from a centre on the
// chord (the chord's midpoint): one piece per triangle of its faces, each face triangulated
// through its crossing points and pierce point. In that star, the crack is the fan of triangles
// (centre, p, q) over the crack's traces p-q on the faces (a face holding exactly two crack
// points); these faces open like a complete cut's (split_crack_nodes), while the centre and the
// pierce points, on the blade, stay shared: the crack closes at the blade (the partial cuts of
// Knee Arthroscopy VR, cases 3 to 5 of Fig. 14: an edge and two faces, two edges, and so on, all
// come out of the same rule).
//
// Conformity: a face is triangulated from its own points only, the same way from both of its
// tets, and every tet holding a split edge or a pierced face is split too (star from its
// centroid, without a crack), so the result has no hanging node.
//
// Positions: each new node is an affine combination (edge t, face or tet barycentric coordinates)
// of its tet's nodes, computed in the current configuration and applied alike to rest, x and v,
// so pieces are positive in both configurations and the rest volume is unchanged. A pierce point
// and a centre are kept at least kFrontMargin (barycentric) inside their face or tet, so no piece
// is flat; the crack is then off the blade by at most that fraction of the tet.

#include <span>
#include <vector>

#include "sim/core/types.h"
#include "sim/cut/cut_mesh.h"
#include "sim/cut/cut_surface.h"
#include "sim/mesh/tet_mesh.h"

namespace incise::sim::cut {

inline constexpr Real kFrontMargin = 0.05;

struct FrontSplitReport {
  int front_tets = 0;             // tets the blade's edge is inside
  int split_tets = 0;             // tets split (front tets and their neighbours for conformity)
  int first_new_node = 0;         // nodes [first_new_node, #nodes) are new
  std::vector<int> changed_tets;  // slots replaced or appended, ascending
  Triangles crack_faces;          // the opened crack faces, both sides, final node indices
};

// Whether the segment a + s (b - a), s in [0, 1], passes through the interior of tet t
// (positions x, positively oriented), and the part inside it, [s0, s1].
bool chord_in_tet(const Points& x, const Tets& tets, int t, const Vec3& a, const Vec3& b, Real& s0,
                  Real& s1);

// The tets (slots, ascending) whose interior the blade edge (a, b) crosses in positions x: the
// ones split_front_tets calls front tets. out is cleared first. O(#tets), a box test per tet.
void blade_front_tets(const Points& x, const Tets& tets, const Vec3& a, const Vec3& b,
                      std::vector<int>& out);

// Splits, in place, the tets of mesh that the blade edge (a, b) [m, current configuration] is
// inside, along surface (the surface swept so far, ending at the blade), and opens the crack
// behind the blade. Nodes are appended to rest, x, v; a split tet's first piece takes its slot,
// the others are appended with its label; tets whose node moved to a crack copy are rewritten.
// Does nothing if the blade is inside no tet. Throws std::invalid_argument like cut_mesh.
FrontSplitReport split_front_tets(TetMesh& mesh, const CutSurface& surface, const Vec3& a,
                                  const Vec3& b, const CutOptions& options = {});

// A chord of its own per tet: the crack in tet ends on the segment (a, b) (clipped to the tet)
// instead of on one blade for all. What a stroke's end uses to keep the partial crack along the
// path of the blade's tip (ProgressiveCutter::end_stroke). A chord that misses its tet is skipped.
// Throws std::invalid_argument as split_front_tets, or for a tet out of range.
struct FrontChord {
  int tet = -1;
  Vec3 a = Vec3::Zero(), b = Vec3::Zero();
};
FrontSplitReport split_front_chords(TetMesh& mesh, const CutSurface& surface,
                                    std::span<const FrontChord> chords,
                                    const CutOptions& options = {});

}  // namespace incise::sim::cut
