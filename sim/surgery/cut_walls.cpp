#include "sim/surgery/cut_walls.h"

#include <algorithm>

namespace incise::sim::surgery {

CutWalls::CutWalls(const Points& rest, const Triangles& faces) : rest_(rest) {
  tree_.build(rest_, faces);
}

void CutWalls::classify(const Points& rest, const BoundarySurface& surface,
                        std::vector<std::uint8_t>& flags) {
  const auto faces = static_cast<std::size_t>(surface.faces.rows());
  flags.resize(faces);
  next_.clear();
  for (std::size_t f = 0; f < faces; ++f) {
    Vec3 centre = Vec3::Zero();
    for (int k = 0; k < 3; ++k) {
      const int node =
          surface.nodes[static_cast<std::size_t>(surface.faces(static_cast<int>(f), k))];
      centre += rest.row(node).transpose();
    }
    centre /= 3;
    Entry entry{centre.x(), centre.y(), centre.z(), 0};
    const auto it = std::lower_bound(known_.begin(), known_.end(), entry);
    if (it != known_.end() && !(entry < *it)) {
      entry.wall = it->wall;
    } else {
      tree_.overlapping_triangles(rest_, collide::Sphere{centre, kOnSurface}, slots_);
      entry.wall = slots_.empty() ? 1 : 0;
    }
    flags[f] = entry.wall;
    next_.push_back(entry);
  }
  std::sort(next_.begin(), next_.end());
  known_.swap(next_);
}

}  // namespace incise::sim::surgery
