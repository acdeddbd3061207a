#include "sim/mesh/mesh_quality.h"

#include <algorithm>
#include <limits>
#include <numbers>

#include "sim/mesh/tet_adjacency.h"
#include "sim/mesh/tet_mesh.h"

namespace incise::sim {
namespace {

// Edge e joins local nodes kTetEdges[e]; the two faces that hold it are those opposite the
// other two nodes.
constexpr int kFacesAtEdge[6][2] = {{2, 3}, {1, 3}, {1, 2}, {0, 3}, {0, 2}, {0, 1}};

void add(QualityRange& range, Real value, int count) {
  if (count == 0) {
    range = {value, value, value};
  } else {
    range.min = std::min(range.min, value);
    range.max = std::max(range.max, value);
    range.mean += value;
  }
}

template <std::size_t N>
int bucket(const std::array<Real, N>& upper_edges, Real value) {
  return static_cast<int>(std::upper_bound(upper_edges.begin(), upper_edges.end(), value) -
                          upper_edges.begin());
}

}  // namespace

TetQuality tet_quality(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const Vec3 p[4] = {a, b, c, d};
  TetQuality quality;
  quality.volume = signed_volume(a, b, c, d);
  for (const auto& edge : kTetEdges) {
    quality.longest_edge = std::max(quality.longest_edge, (p[edge[1]] - p[edge[0]]).norm());
  }
  // Area vectors (twice the area, outward for a positively oriented tet).
  Vec3 normals[4];
  Real area_sum = 0;
  for (int k = 0; k < 4; ++k) {
    const auto& f = kTetFaces[k];
    normals[k] = (p[f[1]] - p[f[0]]).cross(p[f[2]] - p[f[0]]);
    area_sum += normals[k].norm() / 2;
  }
  // longest / (2 sqrt(6) r) with r = 3 |V| / area_sum.
  const Real abs_volume = std::abs(quality.volume);
  quality.aspect_ratio =
      abs_volume > 0 ? quality.longest_edge * area_sum / (6 * std::sqrt(Real(6)) * abs_volume)
                     : std::numeric_limits<Real>::infinity();
  // The interior dihedral angle at an edge is pi minus the angle between the outward normals
  // of its two faces; atan2 keeps it accurate near 0 and pi, where acos of a dot product is not.
  quality.min_dihedral = std::numbers::pi;
  quality.max_dihedral = 0;
  for (const auto& faces : kFacesAtEdge) {
    const Vec3& m = normals[faces[0]];
    const Vec3& n = normals[faces[1]];
    const Real angle = std::numbers::pi - std::atan2(m.cross(n).norm(), m.dot(n));
    quality.min_dihedral = std::min(quality.min_dihedral, angle);
    quality.max_dihedral = std::max(quality.max_dihedral, angle);
  }
  return quality;
}

std::vector<TetQuality> mesh_quality(const Points& points, const Tets& tets) {
  std::vector<TetQuality> qualities(static_cast<std::size_t>(tets.rows()));
  for (Eigen::Index t = 0; t < tets.rows(); ++t) {
    qualities[static_cast<std::size_t>(t)] =
        tet_quality(row3(points, tets(t, 0)), row3(points, tets(t, 1)), row3(points, tets(t, 2)),
                    row3(points, tets(t, 3)));
  }
  return qualities;
}

QualitySummary summarize_quality(const Points& points, const Tets& tets) {
  QualitySummary summary;
  int num_shaped = 0;  // non-degenerate tets, over which the aspect ratio range goes
  for (const TetQuality& quality : mesh_quality(points, tets)) {
    const int count = summary.num_tets++;
    summary.total_volume += quality.volume;
    add(summary.volume, quality.volume, count);
    add(summary.min_dihedral, quality.min_dihedral, count);
    add(summary.max_dihedral, quality.max_dihedral, count);
    if (is_degenerate(quality)) {
      ++summary.num_degenerate;
    } else {
      if (quality.volume < 0) ++summary.num_inverted;
      add(summary.aspect_ratio, quality.aspect_ratio, num_shaped++);
    }
    ++summary.aspect_ratio_histogram[bucket(kAspectRatioBucketEdges, quality.aspect_ratio)];
    ++summary.min_dihedral_histogram[bucket(kMinDihedralBucketEdgesDeg,
                                            quality.min_dihedral * 180 / std::numbers::pi)];
  }
  if (summary.num_tets > 0) {
    summary.volume.mean /= summary.num_tets;
    summary.min_dihedral.mean /= summary.num_tets;
    summary.max_dihedral.mean /= summary.num_tets;
  }
  if (num_shaped > 0) summary.aspect_ratio.mean /= num_shaped;
  return summary;
}

}  // namespace incise::sim
