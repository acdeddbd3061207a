#include "sim/render/cut_opening.h"

#include <Eigen/Geometry>

namespace incise::render {

void open_cut_walls(const SurfaceFaces& F, const std::vector<std::uint8_t>& cut_faces, double gape,
                    SurfacePositions& V, std::vector<double>& scratch) {
  if (static_cast<Eigen::Index>(cut_faces.size()) != F.rows() || gape <= 0) return;
  // Per vertex: the sum of its wall faces' area vectors (3) and of their areas (1).
  scratch.assign(static_cast<std::size_t>(V.rows()) * 4, 0.0);
  bool any = false;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    if (cut_faces[static_cast<std::size_t>(f)] == 0) continue;
    any = true;
    const Eigen::Vector3d a = V.row(F(f, 0)).transpose();
    const Eigen::Vector3d area =
        (V.row(F(f, 1)).transpose() - a).cross(V.row(F(f, 2)).transpose() - a);
    const double size = area.norm();
    for (int k = 0; k < 3; ++k) {
      double* s = &scratch[static_cast<std::size_t>(F(f, k)) * 4];
      s[0] += area.x();
      s[1] += area.y();
      s[2] += area.z();
      s[3] += size;
    }
  }
  if (!any) return;
  for (Eigen::Index v = 0; v < V.rows(); ++v) {
    const double* s = &scratch[static_cast<std::size_t>(v) * 4];
    if (!(s[3] > 0)) continue;
    // |sum| / total * (sum / |sum|) = sum / total.
    V.row(v) -= 0.5 * gape * Eigen::RowVector3d(s[0], s[1], s[2]) / s[3];
  }
}

}  // namespace incise::render
