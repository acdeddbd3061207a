#include "sim/cut/cut_mesh.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <tuple>

#include "sim/cut/crack_nodes.h"
#include "sim/cut/edge_cuts.h"
#include "sim/mesh/tet_adjacency.h"

namespace incise::sim::cut {
namespace {

void check_mesh(const TetMesh& mesh) {
  const auto nodes = mesh.rest.rows();
  if (mesh.x.rows() != nodes || mesh.v.rows() != nodes) {
    throw std::invalid_argument("cut_mesh: rest, x and v have " + std::to_string(nodes) + ", " +
                                std::to_string(mesh.x.rows()) + " and " +
                                std::to_string(mesh.v.rows()) + " rows");
  }
  if (mesh.labels.size() != mesh.tets.rows()) {
    throw std::invalid_argument("cut_mesh: " + std::to_string(mesh.labels.size()) + " labels for " +
                                std::to_string(mesh.tets.rows()) + " tets");
  }
  if (mesh.tets.size() > 0 && (mesh.tets.minCoeff() < 0 || mesh.tets.maxCoeff() >= nodes)) {
    throw std::invalid_argument("cut_mesh: a tet holds a node index outside [0, " +
                                std::to_string(nodes) + ")");
  }
}

FaceKey sorted_face(int a, int b, int c) {
  FaceKey key = {a, b, c};
  std::sort(key.begin(), key.end());
  return key;
}

// A face of the refined mesh seen from one tet: slot and local face (opposite corner).
struct FaceSide {
  int tet = 0;
  int local = 0;
};

int corner_not_in(const Tets& tets, int t, const FaceKey& face) {
  for (int k = 0; k < 4; ++k) {
    if (!std::binary_search(face.begin(), face.end(), tets(t, k))) return k;
  }
  return -1;
}

// A piece of a cut tet: its slot and side (0 or 1, -1 for a partially cut tet's piece).
struct Piece {
  int slot = 0;
  int side = -1;
};

}  // namespace

CutReport cut_mesh(TetMesh& mesh, const CutSurface& surface, const CutOptions& options) {
  return cut_mesh_active(mesh, surface, {}, options);
}

CutReport cut_mesh_active(TetMesh& mesh, const CutSurface& surface, std::span<const char> active,
                          const CutOptions& options) {
  check_mesh(mesh);
  if (!active.empty() && active.size() != static_cast<std::size_t>(mesh.num_tets())) {
    throw std::invalid_argument("cut_mesh_active: " + std::to_string(active.size()) +
                                " active flags for " + std::to_string(mesh.num_tets()) + " tets");
  }
  const auto is_active = [&active](int t) {
    return active.empty() || active[static_cast<std::size_t>(t)] != 0;
  };
  const int num_nodes = mesh.num_nodes();
  const int num_tets = mesh.num_tets();
  const EdgeCuts crossings = find_edge_cuts(mesh.x, unique_edges(mesh.tets), surface, options.snap);
  const auto on_surface = [&crossings](int node) {
    return crossings.on_surface[static_cast<std::size_t>(node)] != 0;
  };
  CutReport report;
  report.first_new_node = num_nodes;
  report.snapped_nodes = static_cast<int>(
      std::count(crossings.on_surface.begin(), crossings.on_surface.end(), char{1}));

  // Step 2: cases; the crossed edges of completely cut tets are split.
  std::vector<TetCutPattern> patterns(static_cast<std::size_t>(num_tets));
  std::vector<char> split(crossings.cuts.size(), 0);
  for (int t = 0; t < num_tets; ++t) {
    std::array<bool, 6> edge_cut{};
    std::array<bool, 4> on{};
    bool touched = false;
    for (int e = 0; e < 6; ++e) {
      edge_cut[e] = find_cut(crossings, mesh.tets(t, kTetEdges[e][0]),
                             mesh.tets(t, kTetEdges[e][1])) != nullptr;
      touched = touched || edge_cut[e];
    }
    for (int k = 0; k < 4; ++k) {
      on[k] = on_surface(mesh.tets(t, k));
      touched = touched || on[k];
    }
    if (!touched || !is_active(t)) continue;
    TetCutPattern& pattern = patterns[static_cast<std::size_t>(t)];
    pattern = classify_tet_cut(edge_cut, on);
    if (pattern.kind == TetCutCase::none) continue;
    ++report.cases[static_cast<std::size_t>(pattern.kind)];
    for (int e = 0; e < 6; ++e) {
      if (!edge_cut[e]) continue;
      const EdgeCut* cut =
          find_cut(crossings, mesh.tets(t, kTetEdges[e][0]), mesh.tets(t, kTetEdges[e][1]));
      split[static_cast<std::size_t>(cut - crossings.cuts.data())] = 1;
    }
  }
  std::vector<int> middle(crossings.cuts.size(), -1);
  for (std::size_t c = 0; c < crossings.cuts.size(); ++c) {
    if (!split[c]) continue;
    middle[c] = num_nodes + static_cast<int>(report.new_nodes.size());
    report.new_nodes.push_back({crossings.cuts[c].a, crossings.cuts[c].b, crossings.cuts[c].t});
  }

  // Step 4, faces with 3 nodes on the surface (before the tets change): opened where the surface
  // passes between the two tets' opposite nodes.
  std::vector<FaceKey> opened;
  std::vector<FaceSide> crack_sides;
  if (std::any_of(crossings.on_surface.begin(), crossings.on_surface.end(),
                  [](char on) { return on != 0; })) {
    const Tets neighbours = face_neighbours(mesh.tets);
    std::vector<Real> hits;
    for (int t = 0; t < num_tets; ++t) {
      for (int k = 0; k < 4; ++k) {
        const int u = neighbours(t, k);
        if (u < t || !is_active(t) || !is_active(u)) continue;
        const int a = mesh.tets(t, kTetFaces[k][0]);
        const int b = mesh.tets(t, kTetFaces[k][1]);
        const int c = mesh.tets(t, kTetFaces[k][2]);
        if (!on_surface(a) || !on_surface(b) || !on_surface(c)) continue;
        const FaceKey face = sorted_face(a, b, c);
        const int w = mesh.tets(t, k);
        const int ku = corner_not_in(mesh.tets, u, face);
        const int w_other = mesh.tets(u, ku);
        if (on_surface(w) || on_surface(w_other)) continue;
        segment_hits(surface, row3(mesh.x, w), row3(mesh.x, w_other), hits);
        if (hits.empty()) continue;
        opened.push_back(face);
        crack_sides.push_back({t, k});
        crack_sides.push_back({u, ku});
        ++report.faces_opened;
      }
    }
  }

  // Step 3: bisection, the first piece of a tet in its slot, the others appended.
  std::vector<std::array<int, 4>> new_tets;  // appended after the existing slots
  std::vector<int> new_labels;
  std::vector<std::array<int, 4>> pieces;
  std::vector<EdgeSplit> splits;
  std::vector<Piece> cut_pieces;
  for (int t = 0; t < num_tets; ++t) {
    splits.clear();
    for (const auto& edge : kTetEdges) {
      const EdgeCut* cut = find_cut(crossings, mesh.tets(t, edge[0]), mesh.tets(t, edge[1]));
      if (cut == nullptr) continue;
      const int mid = middle[static_cast<std::size_t>(cut - crossings.cuts.data())];
      if (mid >= 0) splits.push_back({cut->a, cut->b, mid});
    }
    if (splits.empty()) continue;
    std::sort(splits.begin(), splits.end(), [](const EdgeSplit& p, const EdgeSplit& q) {
      return std::tie(p.a, p.b) < std::tie(q.a, q.b);
    });
    pieces.clear();
    const std::array<int, 4> tet = {mesh.tets(t, 0), mesh.tets(t, 1), mesh.tets(t, 2),
                                    mesh.tets(t, 3)};
    bisect_tet(tet, splits, pieces);
    const TetCutPattern& pattern = patterns[static_cast<std::size_t>(t)];
    const bool cut = pattern.kind != TetCutCase::none;
    if (!cut) ++report.refined_tets;
    cut_pieces.clear();
    for (std::size_t p = 0; p < pieces.size(); ++p) {
      int slot = t;
      if (p == 0) {
        for (int k = 0; k < 4; ++k)
          mesh.tets(t, k) = pieces[0][static_cast<std::size_t>(k)];
      } else {
        slot = num_tets + static_cast<int>(new_tets.size());
        new_tets.push_back(pieces[p]);
        new_labels.push_back(mesh.labels(t));
      }
      report.changed_tets.push_back(slot);
      if (!cut) continue;
      // A piece's side is that of its original nodes off the surface (it has at least one).
      int side = -1;
      for (int corner : pieces[p]) {
        for (int k = 0; k < 4; ++k) {
          if (tet[static_cast<std::size_t>(k)] != corner) continue;
          const int s = pattern.side[static_cast<std::size_t>(k)];
          if (s >= 0 && side >= 0 && s != side) {
            throw std::logic_error("cut_mesh: a piece of tet " + std::to_string(t) +
                                   " lies on both sides of the cut");
          }
          if (s >= 0) side = s;
        }
      }
      cut_pieces.push_back({slot, side});
    }
    // Step 4, inside a cut tet: the faces between pieces of different sides.
    for (std::size_t p = 0; p < cut_pieces.size(); ++p) {
      for (std::size_t q = p + 1; q < cut_pieces.size(); ++q) {
        if (cut_pieces[p].side < 0 || cut_pieces[q].side < 0 ||
            cut_pieces[p].side == cut_pieces[q].side) {
          continue;
        }
        FaceKey face{};
        int shared = 0;
        for (int corner : pieces[p]) {
          if (std::find(pieces[q].begin(), pieces[q].end(), corner) != pieces[q].end()) {
            if (shared < 3) face[static_cast<std::size_t>(shared)] = corner;
            ++shared;
          }
        }
        if (shared != 3) continue;
        std::sort(face.begin(), face.end());
        opened.push_back(face);
        for (std::size_t r : {p, q}) {
          int local = 0;
          while (std::binary_search(face.begin(), face.end(),
                                    pieces[r][static_cast<std::size_t>(local)]))
            ++local;
          crack_sides.push_back({cut_pieces[r].slot, local});
        }
      }
    }
  }
  const int total_tets = num_tets + static_cast<int>(new_tets.size());
  mesh.tets.conservativeResize(total_tets, 4);
  mesh.labels.conservativeResize(total_tets);
  for (std::size_t p = 0; p < new_tets.size(); ++p) {
    const auto row = static_cast<Eigen::Index>(num_tets + static_cast<int>(p));
    for (int k = 0; k < 4; ++k)
      mesh.tets(row, k) = new_tets[p][static_cast<std::size_t>(k)];
    mesh.labels(row) = new_labels[p];
  }

  // Step 5: one copy of each crack node per side.
  std::vector<FaceKey> opened_sorted = opened;
  std::sort(opened_sorted.begin(), opened_sorted.end());
  opened_sorted.erase(std::unique(opened_sorted.begin(), opened_sorted.end()), opened_sorted.end());
  const auto num_opened = opened_sorted.size();
  std::vector<int> copy_of;
  std::vector<NodeRepoint> repoints;
  split_crack_nodes(mesh.tets, opened_sorted, num_nodes + static_cast<int>(report.new_nodes.size()),
                    copy_of, repoints);
  report.faces_closed = static_cast<int>(num_opened - opened_sorted.size());
  for (int source : copy_of)
    report.new_nodes.push_back({source, -1, 0});
  for (const NodeRepoint& r : repoints) {
    mesh.tets(r.tet, r.corner) = r.node;
    report.changed_tets.push_back(r.tet);
  }

  // New node states: on an edge, the same t in rest, current positions and velocities.
  const int total_nodes = num_nodes + static_cast<int>(report.new_nodes.size());
  mesh.rest.conservativeResize(total_nodes, 3);
  mesh.x.conservativeResize(total_nodes, 3);
  mesh.v.conservativeResize(total_nodes, 3);
  for (int i = num_nodes; i < total_nodes; ++i) {
    const NodeOrigin& origin = report.new_nodes[static_cast<std::size_t>(i - num_nodes)];
    for (Points* points : {&mesh.rest, &mesh.x, &mesh.v}) {
      if (origin.b < 0) {
        points->row(i) = points->row(origin.a);
      } else {
        points->row(i) = (1 - origin.t) * points->row(origin.a) + origin.t * points->row(origin.b);
      }
    }
  }

  std::sort(report.changed_tets.begin(), report.changed_tets.end());
  report.changed_tets.erase(std::unique(report.changed_tets.begin(), report.changed_tets.end()),
                            report.changed_tets.end());

  // The crack's boundary faces: each side of an opened face whose two sides now differ (at a
  // crack front whose 3 nodes all stayed shared, the face closes again and is interior).
  std::vector<std::array<int, 3>> faces;
  for (std::size_t f = 0; f + 1 < crack_sides.size(); f += 2) {
    std::array<std::array<int, 3>, 2> side_faces;
    for (int s = 0; s < 2; ++s) {
      const FaceSide& fs = crack_sides[f + static_cast<std::size_t>(s)];
      for (int c = 0; c < 3; ++c)
        side_faces[static_cast<std::size_t>(s)][static_cast<std::size_t>(c)] =
            mesh.tets(fs.tet, kTetFaces[fs.local][c]);
    }
    if (sorted_face(side_faces[0][0], side_faces[0][1], side_faces[0][2]) ==
        sorted_face(side_faces[1][0], side_faces[1][1], side_faces[1][2])) {
      continue;
    }
    faces.push_back(side_faces[0]);
    faces.push_back(side_faces[1]);
  }
  report.crack_faces.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    for (int c = 0; c < 3; ++c)
      report.crack_faces(static_cast<Eigen::Index>(f), c) = faces[f][static_cast<std::size_t>(c)];
  }
  return report;
}

}  // namespace incise::sim::cut
