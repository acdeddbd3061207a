#include "sim/mesh/mesh_info.h"

#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>

#include "sim/mesh/mesh_quality.h"

namespace incise::sim {
namespace {

constexpr Real kDegPerRad = 180 / std::numbers::pi;

void print_range(std::ostream& out, const char* what, const QualityRange& range, Real scale) {
  out << what << ": min " << range.min * scale << ", max " << range.max * scale << ", mean "
      << range.mean * scale << "\n";
}

void print_vec(std::ostream& out, const Vec3& v) {
  out << "[" << v(0) << ", " << v(1) << ", " << v(2) << "]";
}

template <std::size_t N, std::size_t M>
void print_histogram(std::ostream& out, const char* what, Real low, Real high,
                     const std::array<Real, N>& upper_edges, const std::array<int, M>& counts) {
  out << what << ":";
  for (std::size_t b = 0; b < M; ++b) {
    out << (b == 0 ? " [" : ", [") << (b == 0 ? low : upper_edges[b - 1]) << ", ";
    if (b < N) {
      out << upper_edges[b] << ")";
    } else {
      out << high << "]";
    }
    out << " " << counts[b];
  }
  out << "\n";
}

}  // namespace

void print_mesh_info(const TetMesh& mesh, std::ostream& out) {
  out << "nodes: " << mesh.num_nodes() << "\n";
  out << "tets: " << mesh.num_tets() << "\n";
  std::map<int, int> tets_per_label;
  for (int t = 0; t < mesh.num_tets(); ++t)
    ++tets_per_label[mesh.labels(t)];
  out << "labels (label: tets):";
  const char* separator = " ";
  for (const auto& [label, count] : tets_per_label) {
    out << separator << label << ": " << count;
    separator = ", ";
  }
  out << "\n";
  if (mesh.num_nodes() > 0) {
    out << "bounding box [m]: ";
    print_vec(out, mesh.rest.colwise().minCoeff().transpose());
    out << " to ";
    print_vec(out, mesh.rest.colwise().maxCoeff().transpose());
    out << "\n";
  }
  const QualitySummary summary = summarize_quality(mesh.rest, mesh.tets);
  out << "total volume [m^3]: " << summary.total_volume << "\n";
  print_range(out, "tet volume [m^3]", summary.volume, 1);
  print_range(out, "aspect ratio (longest edge / (2 sqrt(6) inradius), 1 = regular)",
              summary.aspect_ratio, 1);
  print_range(out, "min dihedral angle [deg]", summary.min_dihedral, kDegPerRad);
  print_range(out, "max dihedral angle [deg]", summary.max_dihedral, kDegPerRad);
  out << "inverted tets: " << summary.num_inverted << "\n";
  out << "degenerate tets: " << summary.num_degenerate << "\n";
  print_histogram(out, "aspect ratio histogram (bucket count)", 1,
                  std::numeric_limits<Real>::infinity(), kAspectRatioBucketEdges,
                  summary.aspect_ratio_histogram);
  print_histogram(out, "min dihedral histogram [deg] (bucket count)", 0,
                  std::acos(Real(1) / 3) * kDegPerRad, kMinDihedralBucketEdgesDeg,
                  summary.min_dihedral_histogram);
}

}  // namespace incise::sim
