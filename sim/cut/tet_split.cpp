#include "sim/cut/tet_split.h"

#include <algorithm>

#include "sim/mesh/tet_adjacency.h"

namespace incise::sim::cut {
namespace {

// Whether the sides (0 or 1 per vertex off the surface) make exactly the crossed edges join A to B.
bool sides_match(const std::array<int, 4>& side, const std::array<bool, 6>& edge_cut) {
  for (int e = 0; e < 6; ++e) {
    const int i = kTetEdges[e][0];
    const int j = kTetEdges[e][1];
    if (side[i] < 0 || side[j] < 0) continue;
    if ((side[i] != side[j]) != edge_cut[e]) return false;
  }
  return true;
}

}  // namespace

TetCutPattern classify_tet_cut(const std::array<bool, 6>& edge_cut,
                               const std::array<bool, 4>& on_surface) {
  std::array<int, 4> off{};
  int num_off = 0;
  for (int k = 0; k < 4; ++k) {
    if (!on_surface[k]) off[num_off++] = k;
  }
  if (num_off < 2) return {};
  // The first vertex off the surface is on side A; try every side for the others.
  const int assignments = 1 << (num_off - 1);
  for (int mask = 1; mask < assignments; ++mask) {
    std::array<int, 4> side = {-1, -1, -1, -1};
    side[off[0]] = 0;
    int num_b = 0;
    for (int m = 1; m < num_off; ++m) {
      side[off[m]] = (mask >> (m - 1)) & 1;
      num_b += side[off[m]];
    }
    if (num_b == 0 || !sides_match(side, edge_cut)) continue;
    const int num_a = num_off - num_b;
    TetCutPattern pattern;
    pattern.side = side;
    if (num_off == 4) {
      pattern.kind = (num_a == 2) ? TetCutCase::split : TetCutCase::tip;
    } else {
      pattern.kind = (num_off == 3) ? TetCutCase::through_vertex : TetCutCase::through_edge;
    }
    return pattern;
  }
  return {};
}

void bisect_tet(const std::array<int, 4>& tet, std::span<const EdgeSplit> splits,
                std::vector<std::array<int, 4>>& out) {
  const std::size_t first = out.size();
  out.push_back(tet);
  for (const EdgeSplit& split : splits) {
    const std::size_t end = out.size();
    for (std::size_t p = first; p < end; ++p) {
      const auto& piece = out[p];
      const auto ia = std::find(piece.begin(), piece.end(), split.a);
      const auto ib = std::find(piece.begin(), piece.end(), split.b);
      if (ia == piece.end() || ib == piece.end()) continue;
      const auto ka = ia - piece.begin();
      const auto kb = ib - piece.begin();
      std::array<int, 4> other = piece;
      other[static_cast<std::size_t>(kb)] = split.middle;
      out[p][static_cast<std::size_t>(ka)] = split.middle;
      out.push_back(other);
    }
  }
}

}  // namespace incise::sim::cut
