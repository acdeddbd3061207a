#include "sim/cut/edge_cuts.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>

namespace incise::sim::cut {

EdgeCuts find_edge_cuts(const Points& x, const Edges& edges, const CutSurface& surface, Real snap) {
  if (!(snap > 0 && snap < 0.5)) {
    throw std::invalid_argument("cut snap fraction " + std::to_string(snap) +
                                " is outside (0, 0.5)");
  }
  EdgeCuts result;
  result.on_surface.assign(static_cast<std::size_t>(x.rows()), 0);
  const Box3 bounds = surface_bounds(surface);
  std::vector<Real> hits;
  std::vector<EdgeCut> crossings;  // before the edges at snapped nodes are dropped
  for (int e = 0; e < static_cast<int>(edges.rows()); ++e) {
    const int a = std::min(edges(e, 0), edges(e, 1));
    const int b = std::max(edges(e, 0), edges(e, 1));
    const Vec3 pa = row3(x, a);
    const Vec3 pb = row3(x, b);
    Box3 edge_box(pa.cwiseMin(pb), pa.cwiseMax(pb));
    if (!edge_box.intersects(bounds)) continue;
    segment_hits(surface, pa, pb, hits);
    if (hits.size() != 1) continue;
    const Real t = hits.front();
    if (t < snap) {
      result.on_surface[static_cast<std::size_t>(a)] = 1;
    } else if (t > 1 - snap) {
      result.on_surface[static_cast<std::size_t>(b)] = 1;
    } else {
      crossings.push_back({a, b, t});
    }
  }
  for (const EdgeCut& cut : crossings) {
    if (!result.on_surface[static_cast<std::size_t>(cut.a)] &&
        !result.on_surface[static_cast<std::size_t>(cut.b)]) {
      result.cuts.push_back(cut);
    }
  }
  std::sort(result.cuts.begin(), result.cuts.end(), [](const EdgeCut& p, const EdgeCut& q) {
    return std::tie(p.a, p.b) < std::tie(q.a, q.b);
  });
  return result;
}

const EdgeCut* find_cut(const EdgeCuts& cuts, int a, int b) {
  if (a > b) std::swap(a, b);
  const auto it = std::lower_bound(cuts.cuts.begin(), cuts.cuts.end(), std::make_pair(a, b),
                                   [](const EdgeCut& c, const std::pair<int, int>& key) {
                                     return std::tie(c.a, c.b) < std::tie(key.first, key.second);
                                   });
  if (it == cuts.cuts.end() || it->a != a || it->b != b) return nullptr;
  return &*it;
}

}  // namespace incise::sim::cut
