#include "sim/mesh/tet_adjacency.h"

#include <algorithm>
#include <array>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>

namespace incise::sim {
namespace {

// A tet face identified by its sorted node triple, with the tet and local face it came from.
struct FaceRecord {
  std::array<int, 3> key;
  int tet;
  int local;
};

// Every tet face, sorted so that the two copies of an interior face are adjacent.
std::vector<FaceRecord> sorted_faces(const Tets& tets) {
  std::vector<FaceRecord> faces;
  faces.reserve(static_cast<std::size_t>(tets.rows()) * 4);
  for (int t = 0; t < static_cast<int>(tets.rows()); ++t) {
    for (int k = 0; k < 4; ++k) {
      std::array<int, 3> key = {tets(t, kTetFaces[k][0]), tets(t, kTetFaces[k][1]),
                                tets(t, kTetFaces[k][2])};
      std::sort(key.begin(), key.end());
      faces.push_back({key, t, k});
    }
  }
  std::sort(faces.begin(), faces.end(), [](const FaceRecord& a, const FaceRecord& b) {
    return std::tie(a.key, a.tet, a.local) < std::tie(b.key, b.tet, b.local);
  });
  return faces;
}

// Calls visit(first, count) for each run of equal keys in sorted faces.
template <typename Visit>
void for_each_face(const std::vector<FaceRecord>& faces, Visit visit) {
  for (std::size_t begin = 0; begin < faces.size();) {
    std::size_t end = begin + 1;
    while (end < faces.size() && faces[end].key == faces[begin].key)
      ++end;
    if (end - begin > 2) {
      throw std::invalid_argument("face (" + std::to_string(faces[begin].key[0]) + ", " +
                                  std::to_string(faces[begin].key[1]) + ", " +
                                  std::to_string(faces[begin].key[2]) + ") is shared by " +
                                  std::to_string(end - begin) + " tets");
    }
    visit(begin, end - begin);
    begin = end;
  }
}

}  // namespace

Edges unique_edges(const Tets& tets) {
  std::vector<std::pair<int, int>> pairs;
  pairs.reserve(static_cast<std::size_t>(tets.rows()) * 6);
  for (Eigen::Index t = 0; t < tets.rows(); ++t) {
    for (const auto& edge : kTetEdges) {
      const int a = tets(t, edge[0]);
      const int b = tets(t, edge[1]);
      pairs.emplace_back(std::min(a, b), std::max(a, b));
    }
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  Edges edges(static_cast<Eigen::Index>(pairs.size()), 2);
  for (std::size_t e = 0; e < pairs.size(); ++e) {
    edges(static_cast<Eigen::Index>(e), 0) = pairs[e].first;
    edges(static_cast<Eigen::Index>(e), 1) = pairs[e].second;
  }
  return edges;
}

TetEdgeIndices tet_edge_indices(const Tets& tets, const Edges& edges) {
  const auto find = [&edges](int a, int b) {
    const std::pair<int, int> key(std::min(a, b), std::max(a, b));
    Eigen::Index low = 0;
    Eigen::Index high = edges.rows();
    while (low < high) {
      const Eigen::Index mid = low + (high - low) / 2;
      if (std::pair<int, int>(edges(mid, 0), edges(mid, 1)) < key) {
        low = mid + 1;
      } else {
        high = mid;
      }
    }
    if (low == edges.rows() || edges(low, 0) != key.first || edges(low, 1) != key.second) {
      throw std::invalid_argument("edge (" + std::to_string(key.first) + ", " +
                                  std::to_string(key.second) + ") is not in the edge list");
    }
    return static_cast<int>(low);
  };
  TetEdgeIndices indices(tets.rows(), 6);
  for (Eigen::Index t = 0; t < tets.rows(); ++t) {
    for (int e = 0; e < 6; ++e) {
      indices(t, e) = find(tets(t, kTetEdges[e][0]), tets(t, kTetEdges[e][1]));
    }
  }
  return indices;
}

NodeTets node_tets(const Tets& tets, int num_nodes) {
  NodeTets result;
  result.offsets.assign(static_cast<std::size_t>(num_nodes) + 1, 0);
  for (Eigen::Index t = 0; t < tets.rows(); ++t) {
    for (int k = 0; k < 4; ++k)
      ++result.offsets[static_cast<std::size_t>(tets(t, k)) + 1];
  }
  for (std::size_t i = 1; i < result.offsets.size(); ++i) {
    result.offsets[i] += result.offsets[i - 1];
  }
  result.tets.resize(static_cast<std::size_t>(result.offsets.back()));
  std::vector<int> next(result.offsets.begin(), result.offsets.end() - 1);
  for (int t = 0; t < static_cast<int>(tets.rows()); ++t) {
    for (int k = 0; k < 4; ++k) {
      result.tets[static_cast<std::size_t>(next[static_cast<std::size_t>(tets(t, k))]++)] = t;
    }
  }
  return result;
}

Tets face_neighbours(const Tets& tets) {
  Tets neighbours = Tets::Constant(tets.rows(), 4, -1);
  const std::vector<FaceRecord> faces = sorted_faces(tets);
  for_each_face(faces, [&](std::size_t first, std::size_t count) {
    if (count != 2) return;
    const FaceRecord& a = faces[first];
    const FaceRecord& b = faces[first + 1];
    neighbours(a.tet, a.local) = b.tet;
    neighbours(b.tet, b.local) = a.tet;
  });
  return neighbours;
}

Triangles boundary_faces(const Tets& tets, std::vector<int>* face_tets) {
  const std::vector<FaceRecord> faces = sorted_faces(tets);
  std::vector<std::pair<int, int>> boundary;  // (tet, local face)
  for_each_face(faces, [&](std::size_t first, std::size_t count) {
    if (count == 1) boundary.emplace_back(faces[first].tet, faces[first].local);
  });
  std::sort(boundary.begin(), boundary.end());
  Triangles triangles(static_cast<Eigen::Index>(boundary.size()), 3);
  if (face_tets != nullptr) face_tets->resize(boundary.size());
  for (std::size_t f = 0; f < boundary.size(); ++f) {
    const auto [tet, local] = boundary[f];
    if (face_tets != nullptr) (*face_tets)[f] = tet;
    for (int c = 0; c < 3; ++c) {
      triangles(static_cast<Eigen::Index>(f), c) = tets(tet, kTetFaces[local][c]);
    }
  }
  return triangles;
}

}  // namespace incise::sim
