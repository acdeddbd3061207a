#include "sim/scene/node_selection.h"

namespace incise::sim {

Real selection_tolerance(const Points& points) {
  if (points.rows() == 0) return 0;
  const Vec3 extent = (points.colwise().maxCoeff() - points.colwise().minCoeff()).transpose();
  return 1e-6 * extent.norm();
}

std::vector<int> nodes_in_box(const Points& points, const Box3& box, Real tolerance) {
  const Vec3 low = box.min().array() - tolerance;
  const Vec3 high = box.max().array() + tolerance;
  std::vector<int> nodes;
  for (int i = 0; i < static_cast<int>(points.rows()); ++i) {
    const Vec3 p = row3(points, i);
    if ((p.array() >= low.array()).all() && (p.array() <= high.array()).all()) nodes.push_back(i);
  }
  return nodes;
}

}  // namespace incise::sim
