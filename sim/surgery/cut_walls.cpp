#include "sim/surgery/cut_walls.h"

#include <bit>
#include <cstdint>

namespace incise::sim::surgery {

std::size_t CutWalls::KeyHash::operator()(const Key& k) const {
  // FNV-1a over the three coordinates' bits (-0 and +0 differ: both cases only cost a search).
  std::uint64_t h = 14695981039346656037ull;
  for (const Real c : {k.x, k.y, k.z}) {
    h ^= std::bit_cast<std::uint64_t>(c);
    h *= 1099511628211ull;
  }
  return static_cast<std::size_t>(h);
}

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
    const Key key{centre.x(), centre.y(), centre.z()};
    std::uint8_t wall;
    if (const auto it = known_.find(key); it != known_.end()) {
      wall = it->second;
    } else {
      tree_.overlapping_triangles(rest_, collide::Sphere{centre, kOnSurface}, slots_);
      wall = slots_.empty() ? 1 : 0;
    }
    flags[f] = wall;
    next_.emplace(key, wall);
  }
  known_.swap(next_);
}

}  // namespace incise::sim::surgery
