#include "sim/cut/simplify_cut.h"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <string>

#include "sim/mesh/tet_adjacency.h"

namespace incise::sim::cut {
namespace {

constexpr int kOmega = -1;           // the virtual vertex closing the boundary
using Simplex = std::array<int, 3>;  // sorted, padded with INT_MAX

Simplex simplex(int a, int b = INT_MAX, int c = INT_MAX) {
  Simplex s = {a, b, c};
  std::sort(s.begin(), s.end());
  return s;
}

// Adds the simplex (up to 3 vertices, INT_MAX padded) and all its faces.
void add_closure(std::vector<Simplex>& link, const Simplex& s) {
  const int n =
      static_cast<int>(std::count_if(s.begin(), s.end(), [](int v) { return v != INT_MAX; }));
  for (int mask = 1; mask < (1 << n); ++mask) {
    Simplex sub = {INT_MAX, INT_MAX, INT_MAX};
    int k = 0;
    for (int i = 0; i < n; ++i) {
      if (mask & (1 << i)) sub[static_cast<std::size_t>(k++)] = s[static_cast<std::size_t>(i)];
    }
    link.push_back(sub);
  }
}

void sort_unique(std::vector<Simplex>& v) {
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
}

// The faces of tet t holding node v, as (face's other two nodes); a face is on the boundary if no
// other tet of star holds it.
bool face_on_boundary(const Tets& tets, const std::vector<int>& star, int t, const Simplex& face) {
  for (int u : star) {
    if (u == t) continue;
    int shared = 0;
    for (int k = 0; k < 4; ++k)
      shared += std::binary_search(face.begin(), face.end(), tets(u, k));
    if (shared == 3) return false;
  }
  return true;
}

// The link of node v from its star (tets holding v), closed by kOmega over the boundary.
std::vector<Simplex> vertex_link(const Tets& tets, const std::vector<int>& star, int v) {
  std::vector<Simplex> link;
  for (int t : star) {
    std::array<int, 3> opposite{};
    int n = 0;
    for (int k = 0; k < 4; ++k) {
      if (tets(t, k) != v) opposite[static_cast<std::size_t>(n++)] = tets(t, k);
    }
    add_closure(link, simplex(opposite[0], opposite[1], opposite[2]));
    for (int skip = 0; skip < 3; ++skip) {
      const int x = opposite[static_cast<std::size_t>((skip + 1) % 3)];
      const int y = opposite[static_cast<std::size_t>((skip + 2) % 3)];
      if (face_on_boundary(tets, star, t, simplex(v, x, y)))
        add_closure(link, simplex(kOmega, x, y));
    }
  }
  sort_unique(link);
  return link;
}

// The link of edge (a, b) from the star of a, closed by kOmega.
std::vector<Simplex> edge_link(const Tets& tets, const std::vector<int>& star_a, int a, int b) {
  std::vector<Simplex> link;
  for (int t : star_a) {
    std::array<int, 2> opposite{};
    int n = 0;
    bool has_b = false;
    for (int k = 0; k < 4; ++k) {
      const int node = tets(t, k);
      has_b = has_b || node == b;
      if (node != a && node != b && n < 2) opposite[static_cast<std::size_t>(n++)] = node;
    }
    if (!has_b) continue;
    add_closure(link, simplex(opposite[0], opposite[1]));
    for (int x : opposite) {
      if (face_on_boundary(tets, star_a, t, simplex(a, b, x)))
        add_closure(link, simplex(kOmega, x));
    }
  }
  sort_unique(link);
  return link;
}

bool link_condition(const Tets& tets, const std::vector<int>& star_a,
                    const std::vector<int>& star_b, int a, int b) {
  const std::vector<Simplex> la = vertex_link(tets, star_a, a);
  const std::vector<Simplex> lb = vertex_link(tets, star_b, b);
  std::vector<Simplex> both;
  std::set_intersection(la.begin(), la.end(), lb.begin(), lb.end(), std::back_inserter(both));
  return both == edge_link(tets, star_a, a, b);
}

Vec3 corner(const Points& p, const Tets& tets, int t, int k) {
  return row3(p, tets(t, k));
}

Real quality_of(const Points& p, const Tets& tets, int t) {
  return tet_quality(corner(p, tets, t, 0), corner(p, tets, t, 1), corner(p, tets, t, 2),
                     corner(p, tets, t, 3));
}

// The boundary faces of star (tets holding v) that hold v, as node triples.
std::vector<std::array<int, 3>> boundary_faces_at(const Tets& tets, const std::vector<int>& star,
                                                  int v) {
  std::vector<std::array<int, 3>> faces;
  for (int t : star) {
    for (const auto& f : kTetFaces) {
      const std::array<int, 3> face = {tets(t, f[0]), tets(t, f[1]), tets(t, f[2])};
      if (std::find(face.begin(), face.end(), v) == face.end()) continue;
      if (face_on_boundary(tets, star, t, simplex(face[0], face[1], face[2])))
        faces.push_back(face);
    }
  }
  return faces;
}

Real plane_distance(const Points& p, const std::array<int, 3>& face, const Vec3& point) {
  const Vec3 a = row3(p, face[0]);
  const Vec3 n = (row3(p, face[1]) - a).cross(row3(p, face[2]) - a);
  const Real norm = n.norm();
  return norm > 0 ? std::abs(n.dot(point - a)) / norm : std::numeric_limits<Real>::infinity();
}

}  // namespace

Real tet_quality(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const Real volume = signed_volume(a, b, c, d);
  const std::array<Vec3, 4> p = {a, b, c, d};
  Real largest_face = 0;
  Real longest = 0;
  for (const auto& f : kTetFaces) {
    largest_face = std::max(
        largest_face,
        (p[static_cast<std::size_t>(f[1])] - p[static_cast<std::size_t>(f[0])])
                .cross(p[static_cast<std::size_t>(f[2])] - p[static_cast<std::size_t>(f[0])])
                .norm() /
            2);
  }
  for (const auto& e : kTetEdges)
    longest = std::max(
        longest, (p[static_cast<std::size_t>(e[0])] - p[static_cast<std::size_t>(e[1])]).norm());
  if (!(largest_face > 0) || !(longest > 0)) return 0;
  return 3 * volume / largest_face / longest;  // the smallest altitude is over the largest face
}

bool link_condition_holds(const Tets& tets, int a, int b) {
  std::vector<int> star_a, star_b;
  for (int t = 0; t < static_cast<int>(tets.rows()); ++t) {
    for (int k = 0; k < 4; ++k) {
      if (tets(t, k) == a) star_a.push_back(t);
      if (tets(t, k) == b) star_b.push_back(t);
    }
  }
  return link_condition(tets, star_a, star_b, a, b);
}

SimplifyReport simplify_cut_region(TetMesh& mesh, std::span<const int> region,
                                   const SimplifyOptions& options, std::span<const char> pinned) {
  const int num_tets = mesh.num_tets();
  if (!pinned.empty() && static_cast<int>(pinned.size()) != mesh.num_nodes()) {
    throw std::invalid_argument("simplify_cut_region: pinned has " + std::to_string(pinned.size()) +
                                " entries for " + std::to_string(mesh.num_nodes()) + " nodes");
  }
  for (int t : region) {
    if (t < 0 || t >= num_tets) {
      throw std::invalid_argument("simplify_cut_region: slot " + std::to_string(t) +
                                  " is outside [0, " + std::to_string(num_tets) + ")");
    }
  }
  SimplifyReport report;
  const NodeTets adjacency = node_tets(mesh.tets, mesh.num_nodes());
  std::vector<std::vector<int>> star(static_cast<std::size_t>(mesh.num_nodes()));
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    const auto begin = adjacency.tets.begin() + adjacency.offsets[static_cast<std::size_t>(i)];
    const auto end = adjacency.tets.begin() + adjacency.offsets[static_cast<std::size_t>(i) + 1];
    star[static_cast<std::size_t>(i)].assign(begin, end);
  }
  std::vector<char> dead(static_cast<std::size_t>(num_tets), 0);
  // The region grown by the tets sharing a node with it.
  std::vector<int> area;
  for (int t : region) {
    for (int k = 0; k < 4; ++k) {
      const auto& s = star[static_cast<std::size_t>(mesh.tets(t, k))];
      area.insert(area.end(), s.begin(), s.end());
    }
  }
  std::sort(area.begin(), area.end());
  area.erase(std::unique(area.begin(), area.end()), area.end());
  const auto region_min = [&]() {
    Real q = std::numeric_limits<Real>::infinity();
    for (int t : area) {
      if (!dead[static_cast<std::size_t>(t)]) q = std::min(q, quality_of(mesh.rest, mesh.tets, t));
    }
    return q;
  };
  report.min_quality_before = region_min();

  // Tries to move node b onto a; returns whether it did.
  const auto try_collapse = [&](int a, int b) {
    if (!pinned.empty() && pinned[static_cast<std::size_t>(b)] != 0) {
      ++report.rejected_pinned;
      return false;
    }
    const auto& sb = star[static_cast<std::size_t>(b)];
    const auto& sa = star[static_cast<std::size_t>(a)];
    // Boundary error.
    const auto faces_b = boundary_faces_at(mesh.tets, sb, b);
    if (!faces_b.empty()) {
      if (boundary_faces_at(mesh.tets, sa, a).empty()) {
        ++report.rejected_boundary;
        return false;
      }
      for (const auto& face : faces_b) {
        bool bad = plane_distance(mesh.rest, face, row3(mesh.rest, a)) > options.boundary_tolerance;
        if (std::find(face.begin(), face.end(), a) == face.end()) {
          std::array<int, 3> moved = face;
          std::replace(moved.begin(), moved.end(), b, a);
          bad = bad ||
                plane_distance(mesh.rest, moved, row3(mesh.rest, b)) > options.boundary_tolerance;
        }
        if (bad) {
          ++report.rejected_boundary;
          return false;
        }
      }
    }
    if (!link_condition(mesh.tets, sa, sb, a, b)) {
      ++report.rejected_topology;
      return false;
    }
    // Inversion and progress over the tets that move.
    Real old_min = std::numeric_limits<Real>::infinity();
    Real new_min = std::numeric_limits<Real>::infinity();
    for (int t : sb) {
      old_min = std::min(old_min, quality_of(mesh.rest, mesh.tets, t));
      bool has_a = false;
      std::array<Vec3, 4> rest_p, x_p;
      for (int k = 0; k < 4; ++k) {
        int node = mesh.tets(t, k);
        has_a = has_a || node == a;
        if (node == b) node = a;
        rest_p[static_cast<std::size_t>(k)] = row3(mesh.rest, node);
        x_p[static_cast<std::size_t>(k)] = row3(mesh.x, node);
      }
      if (has_a) continue;  // removed
      if (!(signed_volume(x_p[0], x_p[1], x_p[2], x_p[3]) > 0)) {
        ++report.rejected_inversion;
        return false;
      }
      const Real q = tet_quality(rest_p[0], rest_p[1], rest_p[2], rest_p[3]);
      if (!(q > 0)) {
        ++report.rejected_inversion;
        return false;
      }
      new_min = std::min(new_min, q);
    }
    if (!(new_min > old_min)) {
      ++report.rejected_quality;
      return false;
    }
    // Collapse: tets holding both die, the others take a for b.
    std::vector<int> moved_star;
    for (int t : std::vector<int>(sb)) {
      bool has_a = false;
      for (int k = 0; k < 4; ++k)
        has_a = has_a || mesh.tets(t, k) == a;
      if (has_a) {
        dead[static_cast<std::size_t>(t)] = 1;
        for (int k = 0; k < 4; ++k) {
          auto& s = star[static_cast<std::size_t>(mesh.tets(t, k))];
          s.erase(std::remove(s.begin(), s.end(), t), s.end());
        }
      } else {
        for (int k = 0; k < 4; ++k) {
          if (mesh.tets(t, k) == b) mesh.tets(t, k) = a;
        }
        moved_star.push_back(t);
      }
    }
    auto& s = star[static_cast<std::size_t>(a)];
    s.insert(s.end(), moved_star.begin(), moved_star.end());
    std::sort(s.begin(), s.end());
    star[static_cast<std::size_t>(b)].clear();
    ++report.collapses;
    return true;
  };

  for (int pass = 0; pass < options.max_passes; ++pass) {
    std::vector<std::pair<Real, int>> slivers;
    for (int t : area) {
      if (dead[static_cast<std::size_t>(t)]) continue;
      const Real q = quality_of(mesh.rest, mesh.tets, t);
      if (q < options.min_quality) slivers.push_back({q, t});
    }
    std::sort(slivers.begin(), slivers.end());
    int done = 0;
    for (const auto& [q, t] : slivers) {
      if (dead[static_cast<std::size_t>(t)] ||
          quality_of(mesh.rest, mesh.tets, t) >= options.min_quality)
        continue;
      // Its edges, shortest first, each way.
      std::array<std::pair<Real, int>, 6> edges;
      for (int e = 0; e < 6; ++e) {
        edges[static_cast<std::size_t>(e)] = {(corner(mesh.rest, mesh.tets, t, kTetEdges[e][0]) -
                                               corner(mesh.rest, mesh.tets, t, kTetEdges[e][1]))
                                                  .norm(),
                                              e};
      }
      std::sort(edges.begin(), edges.end());
      for (const auto& [length, e] : edges) {
        const int p = mesh.tets(t, kTetEdges[e][0]);
        const int r = mesh.tets(t, kTetEdges[e][1]);
        if (try_collapse(p, r) || try_collapse(r, p)) {
          ++done;
          break;
        }
      }
    }
    if (done == 0) break;
  }
  report.min_quality_after = region_min();
  for (int t : area) {
    if (!dead[static_cast<std::size_t>(t)] &&
        quality_of(mesh.rest, mesh.tets, t) < options.min_quality)
      ++report.slivers_left;
  }

  // Compaction, order kept.
  report.tet_map.assign(static_cast<std::size_t>(num_tets), -1);
  int kept = 0;
  for (int t = 0; t < num_tets; ++t) {
    if (dead[static_cast<std::size_t>(t)]) continue;
    report.tet_map[static_cast<std::size_t>(t)] = kept;
    mesh.tets.row(kept) = mesh.tets.row(t);
    mesh.labels(kept) = mesh.labels(t);
    ++kept;
  }
  mesh.tets.conservativeResize(kept, 4);
  mesh.labels.conservativeResize(kept);
  report.node_map.assign(static_cast<std::size_t>(mesh.num_nodes()), -1);
  for (int t = 0; t < kept; ++t) {
    for (int k = 0; k < 4; ++k)
      report.node_map[static_cast<std::size_t>(mesh.tets(t, k))] = 0;
  }
  int nodes = 0;
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    if (report.node_map[static_cast<std::size_t>(i)] < 0) continue;
    report.node_map[static_cast<std::size_t>(i)] = nodes;
    mesh.rest.row(nodes) = mesh.rest.row(i);
    mesh.x.row(nodes) = mesh.x.row(i);
    mesh.v.row(nodes) = mesh.v.row(i);
    ++nodes;
  }
  for (Points* p : {&mesh.rest, &mesh.x, &mesh.v})
    p->conservativeResize(nodes, 3);
  for (int t = 0; t < kept; ++t) {
    for (int k = 0; k < 4; ++k)
      mesh.tets(t, k) = report.node_map[static_cast<std::size_t>(mesh.tets(t, k))];
  }
  return report;
}

}  // namespace incise::sim::cut
