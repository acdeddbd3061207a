#include "sim/cut/crack_nodes.h"

#include <algorithm>
#include <array>
#include <climits>
#include <numeric>
#include <utility>

#include "sim/mesh/tet_adjacency.h"

namespace incise::sim::cut {
namespace {

int find_root(std::vector<int>& parent, int i) {
  while (parent[static_cast<std::size_t>(i)] != i) {
    parent[static_cast<std::size_t>(i)] =
        parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(i)])];
    i = parent[static_cast<std::size_t>(i)];
  }
  return i;
}

// The face shared by tets s and t if they share exactly 3 nodes.
bool shared_face(const Tets& tets, int s, int t, FaceKey& face) {
  int count = 0;
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      if (tets(s, i) == tets(t, j)) {
        if (count == 3) return false;
        face[static_cast<std::size_t>(count++)] = tets(s, i);
      }
    }
  }
  if (count != 3) return false;
  std::sort(face.begin(), face.end());
  return true;
}

// Groups the star of node (its tets, ascending) through the faces at node that are not opened;
// the group of the lowest tet keeps node, every other group gets the next copy.
void group_star(const Tets& tets, const std::vector<int>& star, int node,
                const std::vector<FaceKey>& opened, int first_copy, std::vector<int>& copy_of,
                std::vector<NodeRepoint>& repoints) {
  const int size = static_cast<int>(star.size());
  std::vector<int> parent(star.size());
  std::iota(parent.begin(), parent.end(), 0);
  FaceKey face;
  for (int s = 0; s < size; ++s) {
    for (int t = s + 1; t < size; ++t) {
      if (!shared_face(tets, star[static_cast<std::size_t>(s)], star[static_cast<std::size_t>(t)],
                       face)) {
        continue;
      }
      if (std::binary_search(opened.begin(), opened.end(), face)) continue;
      parent[static_cast<std::size_t>(find_root(parent, s))] = find_root(parent, t);
    }
  }
  std::vector<int> group_node(star.size(), -1);
  bool first_group = true;
  for (int s = 0; s < size; ++s) {
    const auto root = static_cast<std::size_t>(find_root(parent, s));
    if (group_node[root] < 0) {
      if (first_group) {
        group_node[root] = node;
        first_group = false;
      } else {
        group_node[root] = first_copy + static_cast<int>(copy_of.size());
        copy_of.push_back(node);
      }
    }
    if (group_node[root] == node) continue;
    const int tet = star[static_cast<std::size_t>(s)];
    for (int k = 0; k < 4; ++k) {
      if (tets(tet, k) == node) repoints.push_back({tet, k, group_node[root]});
    }
  }
}

// Whether the boundary faces at `node` among the tets of star (after the copies) fail to form a
// single closed fan: the node would be pinched, two sheets of boundary touching at one point.
bool pinched(const Tets& tets, const std::vector<int>& star, int node) {
  std::vector<std::pair<FaceKey, std::array<int, 2>>> faces;  // sorted face, link edge a -> b
  for (int t : star) {
    int corner = -1;
    for (int k = 0; k < 4; ++k) {
      if (tets(t, k) == node) corner = k;
    }
    if (corner < 0) continue;
    for (int k = 0; k < 4; ++k) {
      if (k == corner) continue;
      std::array<int, 3> f = {tets(t, kTetFaces[k][0]), tets(t, kTetFaces[k][1]),
                              tets(t, kTetFaces[k][2])};
      while (f[0] != node)
        std::rotate(f.begin(), f.begin() + 1, f.end());
      FaceKey key = f;
      std::sort(key.begin(), key.end());
      faces.push_back({key, {f[1], f[2]}});
    }
  }
  std::sort(faces.begin(), faces.end());
  std::vector<std::array<int, 2>> link;  // the boundary faces' edges opposite node
  for (std::size_t i = 0; i < faces.size();) {
    std::size_t j = i + 1;
    while (j < faces.size() && faces[j].first == faces[i].first)
      ++j;
    if (j - i > 2) return true;
    if (j - i == 1) link.push_back(faces[i].second);
    i = j;
  }
  if (link.empty()) return false;
  // One cycle: follow a -> b from the first edge and come back after visiting every edge.
  std::sort(link.begin(), link.end());
  for (std::size_t i = 1; i < link.size(); ++i) {
    if (link[i][0] == link[i - 1][0]) return true;
  }
  std::size_t steps = 0;
  int at = link.front()[0];
  do {
    const auto next = std::lower_bound(link.begin(), link.end(), std::array<int, 2>{at, INT_MIN});
    if (next == link.end() || (*next)[0] != at) return true;
    at = (*next)[1];
    ++steps;
  } while (at != link.front()[0] && steps <= link.size());
  return steps != link.size();
}

}  // namespace

void split_crack_nodes(const Tets& tets, std::vector<FaceKey>& opened, int first_copy,
                       std::vector<int>& copy_of, std::vector<NodeRepoint>& repoints) {
  std::vector<int> nodes;
  for (const FaceKey& face : opened)
    nodes.insert(nodes.end(), face.begin(), face.end());
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());

  // The tets around each crack node, in ascending slot order (one pass over all tets).
  const auto index_of = [&nodes](int node) {
    const auto it = std::lower_bound(nodes.begin(), nodes.end(), node);
    return (it != nodes.end() && *it == node) ? static_cast<int>(it - nodes.begin()) : -1;
  };
  std::vector<std::vector<int>> around(nodes.size());
  for (int t = 0; t < static_cast<int>(tets.rows()); ++t) {
    for (int k = 0; k < 4; ++k) {
      const int i = index_of(tets(t, k));
      if (i >= 0) around[static_cast<std::size_t>(i)].push_back(t);
    }
  }

  // Faces at a node that would be pinched close again, until no node is: each round removes
  // faces, so this ends.
  Tets split = tets;
  std::vector<char> active(nodes.size());
  std::vector<int> bad;
  while (true) {
    std::fill(active.begin(), active.end(), 0);
    for (const FaceKey& face : opened) {
      for (int node : face)
        active[static_cast<std::size_t>(index_of(node))] = 1;
    }
    copy_of.clear();
    repoints.clear();
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      if (active[i]) group_star(tets, around[i], nodes[i], opened, first_copy, copy_of, repoints);
    }
    for (const NodeRepoint& r : repoints)
      split(r.tet, r.corner) = r.node;
    bad.clear();
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      if (!active[i]) continue;
      bool is_bad = pinched(split, around[i], nodes[i]);
      for (std::size_t c = 0; c < copy_of.size() && !is_bad; ++c) {
        if (copy_of[c] == nodes[i])
          is_bad = pinched(split, around[i], first_copy + static_cast<int>(c));
      }
      if (is_bad) bad.push_back(nodes[i]);
    }
    for (const NodeRepoint& r : repoints)
      split(r.tet, r.corner) = tets(r.tet, r.corner);
    if (bad.empty()) return;
    std::erase_if(opened, [&bad](const FaceKey& face) {
      return std::any_of(face.begin(), face.end(), [&bad](int node) {
        return std::binary_search(bad.begin(), bad.end(), node);
      });
    });
  }
}

}  // namespace incise::sim::cut
