#pragma once

// Regions of adaptation (Paloc 2006, "Regions of adaptation"): where the mesh
// should be fine, from contact with a tool, high Green strain and high surface bend, with
// hysteresis so that a region does not flicker between refined and decimated. The result is two
// size fields over the rest configuration: one for refine(), one (larger) for Decimator.
//
// Regions are a list of rest-space balls. A ball encloses the rest vertices of the tets that
// made it, so the tets refinement cuts from them keep their centroids inside (the size field's
// membership rule). Lookups cost O(#balls); merge_distance keeps the count low.

#include <limits>
#include <optional>
#include <span>
#include <vector>

#include "sim/core/types.h"
#include "sim/remesh/size_field.h"

namespace incise::sim::remesh {

// What the scene asks for. Each criterion has an `on` level (a tet reaching it is refined) and a
// laxer `off` level (a region already refined stays refined while one of its tets is still past
// off): the hysteresis band.
struct AdaptationCriteria {
  // Contact: the tool acts on the deformed body, so distances are measured in the deformed
  // configuration, from each tool point to each deformed tet (the solid tet, not only its
  // vertices); the tets are then marked in rest space.
  bool contact = false;
  Real contact_radius = 0;   // [m] on: a tool point within this distance of the deformed tet
  Real contact_release = 0;  // [m] off: held while within this distance (>= contact_radius)

  // Green strain E = (F^T F - I) / 2, F = Ds Dm^-1 (constant per tet), by its Frobenius norm.
  bool strain = false;
  Real strain_on = 0.05;
  Real strain_off = 0.03;  // <= strain_on

  // Surface bend at a boundary edge: how far the signed angle between the outward normals of the
  // two boundary faces at the edge has changed from rest [rad], in [0, pi]. Measured relative to
  // rest, so that the box's own corners or a curved organ's rest facets do not count; only
  // bending by the deformation does. Both faces' tets get the value.
  bool curvature = false;
  Real bend_on = 0.35;  // [rad], about 20 degrees
  Real bend_off = 0.2;  // [rad], <= bend_on

  // The target circumradius [m] inside the regions (> 0, finite).
  Real fine_size = 0;
  // Grading outside the regions: the size grows as fine_size + grading * d with the rest distance
  // d from the regions while it is below coarse_size, and is +infinity beyond (no refinement
  // wanted). grading = 0 (or coarse_size = fine_size) gives no band. Set coarse_size to about the
  // unrefined mesh's own circumradius so that the band ends where the mesh is already that fine.
  Real coarse_size = std::numeric_limits<Real>::infinity();
  Real grading = 0;
  // [m] >= 0: the keep field's balls are the regions' balls grown by this much, so that a vertex
  // inserted near a region's edge is not removed and re-inserted as the region moves by a little.
  Real keep_margin = 0;
  // [m] >= 0: a newly marked tet joins the nearest ball whose centre is within this rest distance
  // of its centroid (the ball grows to enclose it) instead of starting a ball of its own. Balls
  // then have radii up to merge_distance + a tet's size.
  Real merge_distance = 0;
};

// A rest-space ball.
struct RegionBall {
  Vec3 center;
  Real radius;
};

// The per-tet outcome of an update.
enum class TetMark : char {
  kCold = 0,  // no criterion past its off level (or the tet is not alive)
  kWarm = 1,  // past an off level, none past its on level: holds a ball it lies in
  kHot = 2,   // past an on level: refined now
};

class AdaptationRegions {
 public:
  // Throws std::invalid_argument for criteria out of range (see the fields).
  explicit AdaptationRegions(const AdaptationCriteria& criteria);

  // Evaluates the criteria on the current state and updates the balls:
  //   1. a ball of the last update is kept if the centroid of a kWarm or kHot tet lies in it, and
  //      dropped otherwise (released as a whole; a warm tet never grows a ball, so a region whose
  //      tets stay between off and on neither creeps nor shrinks);
  //   2. each kHot tet whose rest bounding ball is not inside a ball joins the nearest ball within
  //      merge_distance, else starts one.
  //   rest       #vertices by 3 rest positions [m]
  //   x          #vertices by 3 deformed positions [m]
  //   tets       #tets by 4 vertex indices, positively oriented at rest (rows of dead tets are
  //              not read)
  //   neighbors  #tets by 4: the tet across face k (opposite local vertex k), -1 on the
  //              boundary (face_neighbours(tets), or RemeshMesh::neighbor); read only with
  //              curvature on
  //   alive      #tets flags, 0 = a free slot to skip; empty = all alive
  //   tools      tool points in the deformed configuration [m]; read only with contact on
  // Cost O(#tets * #tools + #tets * #balls + B log B) for B boundary faces; no allocation once
  // the scratch arrays have grown to the mesh.
  // Throws std::invalid_argument for mismatched sizes, a vertex index out of range, or (strain
  // on) an alive tet that is flat or inverted at rest.
  void update(const Points& rest, const Points& x, const Tets& tets, const Tets& neighbors,
              std::span<const char> alive, std::span<const Vec3> tools);

  const std::vector<RegionBall>& balls() const { return balls_; }
  // Per tet, from the last update: the mark, and the measured values: the deformed distance to
  // the nearest tool [m] (+infinity if none is within contact_release, with contact off, or for a
  // dead tet); the Green strain norm; the largest bend [rad] at the tet's boundary edges (0 for
  // criteria that are off and for dead tets).
  const std::vector<TetMark>& marks() const { return marks_; }
  const std::vector<Real>& tool_distance() const { return tool_distance_; }
  const std::vector<Real>& strain() const { return strain_; }
  const std::vector<Real>& bend() const { return bend_; }

  // Where to refine now: fine_size in the balls, the graded band around them, +infinity beyond.
  // A snapshot: later updates do not change it.
  SizeField refine_field() const;
  // Where not to decimate: the same with the balls grown by keep_margin, so its finite region
  // contains refine_field's.
  SizeField keep_field() const;
  // A ball holding every point where refine_field is finite (the balls with their graded band),
  // for RefinementSettings::region; nothing while there is no ball.
  std::optional<RegionHint> refine_hint() const;

 private:
  struct BoundaryEdge {
    int lo, hi;  // the edge's vertices, sorted
    int from;    // the edge's first vertex in the face's outward cyclic order
    int tet, face;
  };
  void measure_bend(const Points& rest, const Points& x, const Tets& tets, const Tets& neighbors,
                    std::span<const char> alive);
  SizeField field(Real margin) const;

  AdaptationCriteria criteria_;
  std::vector<RegionBall> balls_;
  std::vector<TetMark> marks_;
  std::vector<Real> tool_distance_;
  std::vector<Real> strain_;
  std::vector<Real> bend_;
  // Scratch, reused across updates.
  std::vector<RegionBall> next_balls_;
  std::vector<BoundaryEdge> edges_;
};

// The Frobenius norm of the Green strain (F^T F - I) / 2 of the tet whose rest vertices are a..d
// and deformed vertices xa..xd, F = [xb-xa, xc-xa, xd-xa] [b-a, c-a, d-a]^-1.
// Throws std::invalid_argument if the rest tet is flat or inverted (volume <= 0).
Real green_strain_norm(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, const Vec3& xa,
                       const Vec3& xb, const Vec3& xc, const Vec3& xd);

// The distance [m] from p to the solid tet a..d (0 inside), for either orientation; a flat tet
// is measured as its four faces.
Real point_tet_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

}  // namespace incise::sim::remesh
