#include "sim/scene/node_selection.h"

#include <string>

#include "sim/scene/scene.h"
#include "sim/scene/scene_error.h"

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

std::vector<char> held_at_rest(const Scene& scene, const TetMesh& mesh) {
  std::vector<char> held(static_cast<std::size_t>(mesh.num_nodes()), 0);
  const Real tolerance = selection_tolerance(mesh.rest);
  for (std::size_t k = 0; k < scene.constraints.size(); ++k) {
    const Constraint& c = scene.constraints[k];
    const std::string path = "constraints[" + std::to_string(k) + "]";
    if (c.axes != Axes{true, true, true}) {
      throw SceneError(path, "holds only some axes; a body held at rest takes \"fix\": \"xyz\"");
    }
    if (!c.displacement.isZero()) {
      throw SceneError(path, "displaces its nodes; a body held at rest takes \"fix\": \"xyz\"");
    }
    const std::vector<int> nodes = nodes_in_box(mesh.rest, c.where.box, tolerance);
    if (nodes.empty()) throw SceneError(path + ".where", "selects no node");
    for (const int i : nodes)
      held[static_cast<std::size_t>(i)] = 1;
  }
  return held;
}

}  // namespace incise::sim
