#pragma once

#include <array>
#include <cmath>
#include <vector>

#include "sim/core/types.h"

namespace incise::sim {

// Shape measures of one tet.
struct TetQuality {
  Real volume = 0;        // signed volume [m^3], negative for an inverted tet
  Real longest_edge = 0;  // [m]
  // Aspect ratio: longest edge / (2 sqrt(6) inradius), inradius = 3 |V| / (sum of face areas).
  // 1 for the regular tet, larger for worse shapes (about 1.37 for the right-corner tet), +inf
  // for a degenerate one. The factor makes it scale-free and 1 at best, so that it reads like
  // the edge-ratio measures of the literature (it is the reciprocal of the normalised
  // inradius-to-edge ratio).
  Real aspect_ratio = 0;
  // Smallest and largest of the 6 interior dihedral angles [rad], in [0, pi]: acos(1/3) for all
  // six of the regular tet; a sliver has some near 0 and some near pi. Unsigned (the same for
  // a tet and its mirror image); 0 and pi for a flat tet.
  Real min_dihedral = 0;
  Real max_dihedral = 0;
};

// The quality of the tet (a, b, c, d). No NaN for finite input: a flat tet gets aspect ratio
// +inf, and a face of zero area counts as making the angle pi with its neighbours.
TetQuality tet_quality(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

// A tet whose |6 V| is at most this times the cube of its longest edge is degenerate (flat or
// collapsed): scale-free, and far above the round-off of coordinates written with 15 or more
// significant digits.
inline constexpr Real kDegenerateTetRelativeVolume = 1e-12;

inline bool is_degenerate(Real volume, Real longest_edge) {
  const Real l = longest_edge;
  return 6 * std::abs(volume) <= kDegenerateTetRelativeVolume * l * l * l;
}
inline bool is_degenerate(const TetQuality& quality) {
  return is_degenerate(quality.volume, quality.longest_edge);
}

// The quality of each tet of a mesh.
//   points  #nodes by 3 positions [m]
//   tets    #tets by 4 node indices
std::vector<TetQuality> mesh_quality(const Points& points, const Tets& tets);

// Range and mean of one measure over the tets.
struct QualityRange {
  Real min = 0;
  Real max = 0;
  Real mean = 0;
};

// Histogram bucket upper edges, so that a summary reads the same for every mesh.
// Aspect ratio buckets: [1, 1.5), [1.5, 2), [2, 3), [3, 5), [5, 10), [10, inf].
inline constexpr std::array<Real, 5> kAspectRatioBucketEdges = {1.5, 2, 3, 5, 10};
// Minimum dihedral angle buckets [deg]: [0, 5), [5, 10), [10, 20), [20, 30), [30, 40),
// [40, 50), [50, 70.53 = the regular tet's].
inline constexpr std::array<Real, 6> kMinDihedralBucketEdgesDeg = {5, 10, 20, 30, 40, 50};

// Summary over the tets of a mesh; ranges are over all tets (0 if there are none).
struct QualitySummary {
  int num_tets = 0;
  int num_inverted = 0;       // volume < 0 (and not degenerate)
  int num_degenerate = 0;     // |6 V| <= kDegenerateTetRelativeVolume * (longest edge)^3
  Real total_volume = 0;      // sum of signed volumes [m^3]
  QualityRange volume;        // [m^3]
  QualityRange aspect_ratio;  // over the non-degenerate tets (degenerate ones are +inf)
  QualityRange min_dihedral;  // [rad]
  QualityRange max_dihedral;  // [rad]
  std::array<int, kAspectRatioBucketEdges.size() + 1> aspect_ratio_histogram{};
  std::array<int, kMinDihedralBucketEdgesDeg.size() + 1> min_dihedral_histogram{};
};

// The summary of mesh_quality(points, tets).
QualitySummary summarize_quality(const Points& points, const Tets& tets);

}  // namespace incise::sim
