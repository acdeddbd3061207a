#include "sim/cut/front_split.h"

#include <algorithm>
#include <array>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

#include <Eigen/LU>

#include "sim/cut/crack_nodes.h"
#include "sim/cut/edge_cuts.h"
#include "sim/mesh/tet_adjacency.h"

namespace incise::sim::cut {
namespace {

// The chord of segment a + s (b - a), s in [0, 1], inside tet t (current positions), by clipping
// against its four face planes (Cyrus-Beck). Returns false if the chord is empty or shorter than
// 1e-6 of the segment. enter / leave: the face the chord enters / leaves by, or -1 where it starts
// / ends inside the tet (an end of the blade inside the tissue).
bool clip_chord(const Points& x, const Tets& tets, int t, const Vec3& a, const Vec3& b, Real& s0,
                Real& s1, int& enter, int& leave) {
  s0 = 0;
  s1 = 1;
  enter = leave = -1;
  const Vec3 d = b - a;
  for (int k = 0; k < 4; ++k) {
    const Vec3 p = row3(x, tets(t, kTetFaces[k][0]));
    const Vec3 q = row3(x, tets(t, kTetFaces[k][1]));
    const Vec3 r = row3(x, tets(t, kTetFaces[k][2]));
    const Vec3 n = (q - p).cross(r - p);  // outwards
    const Real f = n.dot(a - p);
    const Real g = n.dot(d);
    if (g == 0) {
      if (f > 0) return false;
      continue;
    }
    const Real s = -f / g;
    if (g < 0) {
      if (s > s0) {
        s0 = s;
        enter = k;
      }
    } else if (s < s1) {
      s1 = s;
      leave = k;
    }
  }
  return s1 - s0 > 1e-6;
}

// Weights w (summing to 1) with w_i >= kFrontMargin, the nearest such to w (clamped, renormalised).
template <int N>
Eigen::Matrix<Real, N, 1> inside_weights(Eigen::Matrix<Real, N, 1> w) {
  // Clamp to the margin, then take the excess away from the others proportionally.
  for (int i = 0; i < N; ++i)
    w[i] = std::max(w[i], Real(0));
  w /= w.sum();
  const Real free = 1 - N * kFrontMargin;
  for (int i = 0; i < N; ++i)
    w[i] = kFrontMargin + free * w[i];
  return w;
}

// A new node: an affine combination of up to 4 mesh nodes.
struct Blend {
  std::array<int, 4> nodes{};
  std::array<Real, 4> weights{};
  int count = 0;
};

// Triangulates face (u < v < w) with points on its edges (-1 where none) and a pierce point
// (-1), the same whichever tet asks: a fan from the pierce point, else a fixed pattern per number
// of edge points. Every pair of the face's crack points is joined by an edge of the result.
void triangulate_face(const std::array<int, 3>& c, int m_uv, int m_vw, int m_uw, int pierce,
                      std::vector<std::array<int, 3>>& out) {
  const int u = c[0], v = c[1], w = c[2];
  if (pierce >= 0) {
    std::array<int, 6> cycle{};
    int n = 0;
    for (int node : {u, m_uv, v, m_vw, w, m_uw}) {
      if (node >= 0) cycle[static_cast<std::size_t>(n++)] = node;
    }
    for (int i = 0; i < n; ++i)
      out.push_back({pierce, cycle[static_cast<std::size_t>(i)],
                     cycle[static_cast<std::size_t>((i + 1) % n)]});
    return;
  }
  const int count = (m_uv >= 0) + (m_vw >= 0) + (m_uw >= 0);
  if (count == 0) {
    out.push_back({u, v, w});
  } else if (count == 1) {
    // m on edge (x, y), z opposite.
    const int m = std::max({m_uv, m_vw, m_uw});
    const int x = m_vw >= 0 ? v : u;
    const int y = m_uv >= 0 ? v : w;
    const int z = m_uv >= 0 ? w : (m_vw >= 0 ? u : v);
    out.push_back({x, m, z});
    out.push_back({m, y, z});
  } else if (count == 2) {
    // Corner s shared by the two split edges (s, x) and (s, y), x < y: the corner triangle and
    // the convex quad (m1, x, y, m2) cut along m1-y.
    int s, x, y, m1, m2;
    if (m_uv < 0) {
      s = w, x = u, y = v, m1 = m_uw, m2 = m_vw;
    } else if (m_vw < 0) {
      s = u, x = v, y = w, m1 = m_uv, m2 = m_uw;
    } else {
      s = v, x = u, y = w, m1 = m_uv, m2 = m_vw;
    }
    out.push_back({s, m1, m2});
    out.push_back({m1, x, y});
    out.push_back({m1, y, m2});
  } else {
    out.push_back({u, m_uv, m_uw});
    out.push_back({v, m_vw, m_uv});
    out.push_back({w, m_uw, m_vw});
    out.push_back({m_uv, m_vw, m_uw});
  }
}

std::pair<int, int> edge_key(int a, int b) {
  return {std::min(a, b), std::max(a, b)};
}

}  // namespace

bool chord_in_tet(const Points& x, const Tets& tets, int t, const Vec3& a, const Vec3& b, Real& s0,
                  Real& s1) {
  int enter = -1, leave = -1;
  return clip_chord(x, tets, t, a, b, s0, s1, enter, leave);
}

void blade_front_tets(const Points& x, const Tets& tets, const Vec3& a, const Vec3& b,
                      std::vector<int>& out) {
  out.clear();
  const Box3 blade_box(a.cwiseMin(b), a.cwiseMax(b));
  for (int t = 0; t < static_cast<int>(tets.rows()); ++t) {
    Box3 box;
    for (int k = 0; k < 4; ++k)
      box.extend(row3(x, tets(t, k)));
    if (!box.intersects(blade_box)) continue;
    Real s0 = 0, s1 = 1;
    int enter = -1, leave = -1;
    if (clip_chord(x, tets, t, a, b, s0, s1, enter, leave)) out.push_back(t);
  }
}

FrontSplitReport split_front_tets(TetMesh& mesh, const CutSurface& surface, const Vec3& a,
                                  const Vec3& b, const CutOptions& options) {
  std::vector<int> tets;
  blade_front_tets(mesh.x, mesh.tets, a, b, tets);
  std::vector<FrontChord> chords;
  chords.reserve(tets.size());
  for (const int t : tets)
    chords.push_back({t, a, b});
  return split_front_chords(mesh, surface, chords, options);
}

FrontSplitReport split_front_chords(TetMesh& mesh, const CutSurface& surface,
                                    std::span<const FrontChord> chords, const CutOptions& options) {
  if (mesh.x.rows() != mesh.rest.rows() || mesh.v.rows() != mesh.rest.rows() ||
      mesh.labels.size() != mesh.tets.rows()) {
    throw std::invalid_argument("split_front_tets: the mesh's arrays disagree in size");
  }
  FrontSplitReport report;
  const int num_nodes = mesh.num_nodes();
  const int num_tets = mesh.num_tets();
  report.first_new_node = num_nodes;

  // The front tets and their chords (a + s (b - a), s in [s0, s1], inside the tet).
  struct Front {
    int tet;
    Real s0, s1;
    int enter, leave;
    Vec3 a, b;
  };
  std::vector<Front> fronts;
  for (const FrontChord& c : chords) {
    if (c.tet < 0 || c.tet >= num_tets) {
      throw std::invalid_argument("split_front_chords: tet " + std::to_string(c.tet) +
                                  " is out of range");
    }
    Front f{c.tet, 0, 1, -1, -1, c.a, c.b};
    if (clip_chord(mesh.x, mesh.tets, c.tet, c.a, c.b, f.s0, f.s1, f.enter, f.leave)) {
      fronts.push_back(f);
    }
  }
  report.front_tets = static_cast<int>(fronts.size());
  if (fronts.empty()) return report;

  // Only the tets sharing a node with the front can hold a split edge or a pierced face, or a
  // node on the surface that matters here: the work below is on them only.
  std::vector<char> marked(static_cast<std::size_t>(num_nodes), 0);
  for (const Front& f : fronts) {
    for (int k = 0; k < 4; ++k)
      marked[static_cast<std::size_t>(mesh.tets(f.tet, k))] = 1;
  }
  std::vector<int> near;
  for (int t = 0; t < num_tets; ++t) {
    for (int k = 0; k < 4; ++k) {
      if (marked[static_cast<std::size_t>(mesh.tets(t, k))]) {
        near.push_back(t);
        break;
      }
    }
  }
  Tets near_tets(static_cast<Eigen::Index>(near.size()), 4);
  for (std::size_t i = 0; i < near.size(); ++i)
    near_tets.row(static_cast<Eigen::Index>(i)) = mesh.tets.row(near[i]);
  const Edges edges = unique_edges(near_tets);
  const EdgeCuts crossings = find_edge_cuts(mesh.x, edges, surface, options.snap);
  std::vector<Blend> blends;  // new node k is num_nodes + k
  const auto add_node = [&](const Blend& blend) {
    blends.push_back(blend);
    return num_nodes + static_cast<int>(blends.size()) - 1;
  };

  // Edge points of the front tets' crossed edges, and pierce points of the faces they cross.
  std::map<std::pair<int, int>, int> edge_point;
  std::map<FaceKey, int> pierce_point;
  for (const Front& f : fronts) {
    for (const auto& e : kTetEdges) {
      const EdgeCut* cut = find_cut(crossings, mesh.tets(f.tet, e[0]), mesh.tets(f.tet, e[1]));
      if (cut == nullptr || edge_point.count({cut->a, cut->b})) continue;
      edge_point[{cut->a, cut->b}] = add_node({{cut->a, cut->b}, {1 - cut->t, cut->t}, 2});
    }
    for (const auto& [face, s] : {std::pair{f.enter, f.s0}, std::pair{f.leave, f.s1}}) {
      if (face < 0) continue;
      std::array<int, 3> nodes{};
      for (int c = 0; c < 3; ++c)
        nodes[static_cast<std::size_t>(c)] = mesh.tets(f.tet, kTetFaces[face][c]);
      FaceKey key = nodes;
      std::sort(key.begin(), key.end());
      if (pierce_point.count(key)) continue;
      // Barycentric coordinates of the pierce point in the face (least squares in its plane).
      const Vec3 p = f.a + s * (f.b - f.a);
      const Vec3 q0 = row3(mesh.x, key[0]);
      Eigen::Matrix<Real, 3, 2> m;
      m.col(0) = row3(mesh.x, key[1]) - q0;
      m.col(1) = row3(mesh.x, key[2]) - q0;
      const Eigen::Vector2d uv = (m.transpose() * m).ldlt().solve(m.transpose() * (p - q0));
      const Eigen::Vector3d w = inside_weights<3>(Eigen::Vector3d(1 - uv.sum(), uv[0], uv[1]));
      pierce_point[key] = add_node({{key[0], key[1], key[2]}, {w[0], w[1], w[2]}, 3});
    }
  }

  // The tets to split: the front, and every tet holding a split edge or a pierced face.
  std::vector<char> split(static_cast<std::size_t>(num_tets), 0);
  std::vector<char> is_front(static_cast<std::size_t>(num_tets), 0);
  for (const Front& f : fronts)
    split[static_cast<std::size_t>(f.tet)] = is_front[static_cast<std::size_t>(f.tet)] = 1;
  for (int t : near) {
    for (const auto& e : kTetEdges) {
      if (edge_point.count(edge_key(mesh.tets(t, e[0]), mesh.tets(t, e[1]))))
        split[static_cast<std::size_t>(t)] = 1;
    }
    for (const auto& f : kTetFaces) {
      FaceKey key = {mesh.tets(t, f[0]), mesh.tets(t, f[1]), mesh.tets(t, f[2])};
      std::sort(key.begin(), key.end());
      if (pierce_point.count(key)) split[static_cast<std::size_t>(t)] = 1;
    }
  }

  // Star of each split tet from its centre; crack faces in the front tets.
  std::vector<std::array<int, 4>> appended;
  std::vector<int> appended_labels;
  std::vector<std::array<int, 3>> triangles;
  std::vector<FaceKey> opened;
  std::vector<std::array<int, 4>> pieces;
  const auto point_on = [&edge_point](int p, int q) {
    const auto it = edge_point.find(edge_key(p, q));
    return it == edge_point.end() ? -1 : it->second;
  };
  const auto on_surface = [&crossings](int node) {
    return node < static_cast<int>(crossings.on_surface.size()) &&
           crossings.on_surface[static_cast<std::size_t>(node)] != 0;
  };
  for (int t : near) {
    if (!split[static_cast<std::size_t>(t)]) continue;
    const std::array<int, 4> tet = {mesh.tets(t, 0), mesh.tets(t, 1), mesh.tets(t, 2),
                                    mesh.tets(t, 3)};
    // Centre: the chord's midpoint in a front tet, else the centroid.
    Eigen::Vector4d w = Eigen::Vector4d::Constant(0.25);
    const auto front =
        std::find_if(fronts.begin(), fronts.end(), [t](const Front& f) { return f.tet == t; });
    if (front != fronts.end()) {
      const Vec3 mid = front->a + (front->s0 + front->s1) / 2 * (front->b - front->a);
      const Vec3 x0 = row3(mesh.x, tet[0]);
      Mat3 m;
      for (int k = 1; k < 4; ++k)
        m.col(k - 1) = row3(mesh.x, tet[static_cast<std::size_t>(k)]) - x0;
      const Vec3 l = m.partialPivLu().solve(mid - x0);
      w = inside_weights<4>(Eigen::Vector4d(1 - l.sum(), l[0], l[1], l[2]));
    }
    const int centre = add_node({tet, {w[0], w[1], w[2], w[3]}, 4});
    pieces.clear();
    for (const auto& f : kTetFaces) {
      std::array<int, 3> c = {tet[static_cast<std::size_t>(f[0])],
                              tet[static_cast<std::size_t>(f[1])],
                              tet[static_cast<std::size_t>(f[2])]};
      std::sort(c.begin(), c.end());
      const FaceKey key = c;
      const auto pierce = pierce_point.find(key);
      const int p = pierce == pierce_point.end() ? -1 : pierce->second;
      const int m_uv = point_on(c[0], c[1]), m_vw = point_on(c[1], c[2]),
                m_uw = point_on(c[0], c[2]);
      triangles.clear();
      triangulate_face(c, m_uv, m_vw, m_uw, p, triangles);
      for (const auto& tri : triangles)
        pieces.push_back({tri[0], tri[1], tri[2], centre});
      if (front == fronts.end()) continue;
      // The crack's trace on this face: exactly two crack points.
      std::array<int, 6> crack{};
      int n = 0;
      for (int node : {c[0], c[1], c[2]}) {
        if (on_surface(node)) crack[static_cast<std::size_t>(n++)] = node;
      }
      for (int node : {m_uv, m_vw, m_uw, p}) {
        if (node >= 0) crack[static_cast<std::size_t>(n++)] = node;
      }
      if (n == 2) {
        FaceKey face = {centre, crack[0], crack[1]};
        std::sort(face.begin(), face.end());
        opened.push_back(face);
      }
    }
    for (std::size_t p = 0; p < pieces.size(); ++p) {
      if (p == 0) {
        for (int k = 0; k < 4; ++k)
          mesh.tets(t, k) = pieces[0][static_cast<std::size_t>(k)];
      } else {
        appended.push_back(pieces[p]);
        appended_labels.push_back(mesh.labels(t));
      }
    }
    report.changed_tets.push_back(t);
    ++report.split_tets;
  }
  mesh.tets.conservativeResize(num_tets + static_cast<Eigen::Index>(appended.size()), 4);
  mesh.labels.conservativeResize(mesh.tets.rows());
  for (std::size_t p = 0; p < appended.size(); ++p) {
    const auto row = static_cast<Eigen::Index>(num_tets) + static_cast<Eigen::Index>(p);
    for (int k = 0; k < 4; ++k)
      mesh.tets(row, k) = appended[p][static_cast<std::size_t>(k)];
    mesh.labels(row) = appended_labels[p];
    report.changed_tets.push_back(static_cast<int>(row));
  }

  // New node states, then orientation: a star piece's triangle is on the tet's boundary and its
  // centre inside, so one swap of two corners orients a negative piece.
  const int total = num_nodes + static_cast<int>(blends.size());
  for (Points* points : {&mesh.rest, &mesh.x, &mesh.v}) {
    points->conservativeResize(total, 3);
    for (std::size_t k = 0; k < blends.size(); ++k) {
      Vec3 value = Vec3::Zero();
      for (int i = 0; i < blends[k].count; ++i)
        value += blends[k].weights[static_cast<std::size_t>(i)] *
                 row3(*points, blends[k].nodes[static_cast<std::size_t>(i)]);
      points->row(num_nodes + static_cast<Eigen::Index>(k)) = value.transpose();
    }
  }
  for (int t : report.changed_tets) {
    const auto corner = [&](int k) { return row3(mesh.rest, mesh.tets(t, k)); };
    if (signed_volume(corner(0), corner(1), corner(2), corner(3)) < 0)
      std::swap(mesh.tets(t, 0), mesh.tets(t, 1));
  }

  // Open the crack behind the blade, as in a complete cut.
  std::sort(opened.begin(), opened.end());
  opened.erase(std::unique(opened.begin(), opened.end()), opened.end());
  std::vector<int> copy_of;
  std::vector<NodeRepoint> repoints;
  split_crack_nodes(mesh.tets, opened, total, copy_of, repoints);
  for (Points* points : {&mesh.rest, &mesh.x, &mesh.v}) {
    points->conservativeResize(total + static_cast<Eigen::Index>(copy_of.size()), 3);
    for (std::size_t c = 0; c < copy_of.size(); ++c)
      points->row(total + static_cast<Eigen::Index>(c)) = points->row(copy_of[c]);
  }
  for (const NodeRepoint& r : repoints) {
    mesh.tets(r.tet, r.corner) = r.node;
    report.changed_tets.push_back(r.tet);
  }
  std::sort(report.changed_tets.begin(), report.changed_tets.end());
  report.changed_tets.erase(std::unique(report.changed_tets.begin(), report.changed_tets.end()),
                            report.changed_tets.end());
  // The crack faces now on the boundary: the faces of the changed tets that come from an opened
  // face and are no longer shared (both pieces of an opened face are changed tets).
  const auto original = [&](int node) {
    return node >= total ? copy_of[static_cast<std::size_t>(node - total)] : node;
  };
  std::vector<std::pair<FaceKey, std::array<int, 3>>> sides;  // actual sorted key, oriented face
  for (int t : report.changed_tets) {
    for (const auto& f : kTetFaces) {
      const std::array<int, 3> face = {mesh.tets(t, f[0]), mesh.tets(t, f[1]), mesh.tets(t, f[2])};
      FaceKey key = {original(face[0]), original(face[1]), original(face[2])};
      std::sort(key.begin(), key.end());
      if (!std::binary_search(opened.begin(), opened.end(), key)) continue;
      FaceKey actual = face;
      std::sort(actual.begin(), actual.end());
      sides.push_back({actual, face});
    }
  }
  std::sort(sides.begin(), sides.end());
  std::vector<std::array<int, 3>> crack;
  for (std::size_t i = 0; i < sides.size(); ++i) {
    const bool shared = (i > 0 && sides[i - 1].first == sides[i].first) ||
                        (i + 1 < sides.size() && sides[i + 1].first == sides[i].first);
    if (!shared) crack.push_back(sides[i].second);
  }
  report.crack_faces.resize(static_cast<Eigen::Index>(crack.size()), 3);
  for (std::size_t f = 0; f < crack.size(); ++f) {
    for (int c = 0; c < 3; ++c)
      report.crack_faces(static_cast<Eigen::Index>(f), c) = crack[f][static_cast<std::size_t>(c)];
  }
  return report;
}

}  // namespace incise::sim::cut
