#include "cut_checks.h"

#include <algorithm>
#include <map>
#include <numeric>
#include <random>
#include <utility>

#include <gtest/gtest.h>
#include <Eigen/LU>

#include "sim/mesh/box_mesher.h"
#include "sim/mesh/tet_adjacency.h"

namespace incise::sim::cut::testing {

CutSurface plane_blade(const Vec3& point, const Vec3& normal, Real half) {
  const Vec3 n = normal.normalized();
  const Vec3 helper = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  const Vec3 u = n.cross(helper).normalized();
  const Vec3 w = n.cross(u);
  return blade_sweep(point - half * u - half * w, point + half * u - half * w,
                     point - half * u + half * w, point + half * u + half * w);
}

std::string boundary_problem(const Tets& tets) {
  Triangles faces;
  try {
    faces = boundary_faces(tets);
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  std::map<std::pair<int, int>, int> directed;
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    for (int c = 0; c < 3; ++c)
      ++directed[{faces(f, c), faces(f, (c + 1) % 3)}];
  }
  for (const auto& [edge, count] : directed) {
    const auto reverse = directed.find({edge.second, edge.first});
    if (count != 1 || reverse == directed.end() || reverse->second != 1) {
      return "boundary edge (" + std::to_string(edge.first) + ", " + std::to_string(edge.second) +
             ") is not manifold";
    }
  }
  // Around each vertex, the link edges (a -> b for a face (v, a, b)) must form one cycle.
  std::map<int, std::map<int, int>> link;
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    for (int c = 0; c < 3; ++c)
      link[faces(f, c)][faces(f, (c + 1) % 3)] = faces(f, (c + 2) % 3);
  }
  for (const auto& [vertex, next] : link) {
    const int start = next.begin()->first;
    int at = start;
    std::size_t steps = 0;
    do {
      at = next.at(at);
      ++steps;
    } while (at != start && steps <= next.size());
    if (steps != next.size()) {
      return "boundary vertex " + std::to_string(vertex) + " is pinched (" +
             std::to_string(next.size()) + " faces, a fan of " + std::to_string(steps) + ")";
    }
  }
  return "";
}

std::vector<int> tet_components(const Tets& tets, int* num_components) {
  const Tets neighbours = face_neighbours(tets);
  const int n = static_cast<int>(tets.rows());
  std::vector<int> component(static_cast<std::size_t>(n), -1);
  int count = 0;
  std::vector<int> stack;
  for (int seed = 0; seed < n; ++seed) {
    if (component[static_cast<std::size_t>(seed)] >= 0) continue;
    component[static_cast<std::size_t>(seed)] = count;
    stack.push_back(seed);
    while (!stack.empty()) {
      const int t = stack.back();
      stack.pop_back();
      for (int k = 0; k < 4; ++k) {
        const int u = neighbours(t, k);
        if (u >= 0 && component[static_cast<std::size_t>(u)] < 0) {
          component[static_cast<std::size_t>(u)] = count;
          stack.push_back(u);
        }
      }
    }
    ++count;
  }
  *num_components = count;
  return component;
}

Real triangles_area(const Points& points, const Triangles& triangles) {
  Real area = 0;
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    const Vec3 a = row3(points, triangles(f, 0));
    area += (row3(points, triangles(f, 1)) - a).cross(row3(points, triangles(f, 2)) - a).norm() / 2;
  }
  return area;
}

Real boundary_area(const Points& points, const Tets& tets) {
  return triangles_area(points, boundary_faces(tets));
}

Real min_volume(const Points& points, const Tets& tets) {
  return tet_volumes(points, tets).minCoeff();
}

TetMesh jittered_box(const Vec3& size, const Vec3i& cells, Real jitter, unsigned seed) {
  TetMesh mesh = make_box_mesh(size, cells);
  std::mt19937 random(seed);
  std::uniform_real_distribution<Real> offset(-jitter, jitter);
  const Vec3 cell = size.cwiseQuotient(cells.cast<Real>());
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    const Vec3 p = row3(mesh.rest, i);
    const bool interior = (p.array() > 1e-12).all() && (p.array() < size.array() - 1e-12).all();
    if (!interior) continue;
    for (int c = 0; c < 3; ++c)
      mesh.rest(i, c) += offset(random) * cell[c];
  }
  mesh.x = mesh.rest;
  return mesh;
}

namespace {

// Whether node's position comes from a crossing on an edge (not from a snapped mesh node).
bool from_crossing(const CutReport& report, int node) {
  while (node >= report.first_new_node) {
    const NodeOrigin& origin =
        report.new_nodes[static_cast<std::size_t>(node - report.first_new_node)];
    if (origin.b >= 0) return true;
    node = origin.a;
  }
  return false;
}

Real longest_edge(const Points& points, const Tets& tets) {
  Real longest = 0;
  for (Eigen::Index t = 0; t < tets.rows(); ++t) {
    for (const auto& e : kTetEdges)
      longest =
          std::max(longest, (row3(points, tets(t, e[0])) - row3(points, tets(t, e[1]))).norm());
  }
  return longest;
}

// The tet of mesh whose rest configuration holds point (barycentric coordinates >= -1e-12), or -1.
int containing_tet(const TetMesh& mesh, const Vec3& point) {
  for (int t = 0; t < mesh.num_tets(); ++t) {
    const Vec3 a = row3(mesh.rest, mesh.tets(t, 0));
    Mat3 edges;
    for (int k = 1; k < 4; ++k)
      edges.col(k - 1) = row3(mesh.rest, mesh.tets(t, k)) - a;
    const Vec3 w = edges.partialPivLu().solve(point - a);
    if (w.minCoeff() >= -1e-12 && w.sum() <= 1 + 1e-12) return t;
  }
  return -1;
}

}  // namespace

void expect_cut_invariants(const TetMesh& before, const TetMesh& after, const CutReport& report,
                           const CutSurface& surface, Real snap) {
  ASSERT_EQ(after.rest.rows(), after.x.rows());
  ASSERT_EQ(after.rest.rows(), after.v.rows());
  ASSERT_EQ(after.labels.size(), after.tets.rows());
  EXPECT_EQ(after.num_nodes(), before.num_nodes() + static_cast<int>(report.new_nodes.size()));
  EXPECT_GT(min_volume(after.rest, after.tets), 0);
  EXPECT_GT(min_volume(after.x, after.tets), 0);
  const Real volume = total_volume(before.rest, before.tets);
  EXPECT_NEAR(total_volume(after.rest, after.tets), volume, 1e-9 * volume);
  EXPECT_EQ(boundary_problem(after.tets), "");
  // Subdividing the old boundary keeps its area; the crack adds both of its sides.
  const Real area = boundary_area(after.rest, after.tets);
  EXPECT_NEAR(
      area,
      boundary_area(before.rest, before.tets) + triangles_area(after.rest, report.crack_faces),
      1e-9 * area);
  const Real snapped_tolerance = snap * longest_edge(before.x, before.tets);
  for (Eigen::Index f = 0; f < report.crack_faces.rows(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int node = report.crack_faces(f, c);
      const Real distance = distance_to_surface(surface, row3(after.x, node));
      EXPECT_LE(distance, from_crossing(report, node) ? 1e-9 : snapped_tolerance)
          << "crack node " << node;
    }
  }
  for (int t : report.changed_tets) {
    Vec3 centroid = Vec3::Zero();
    for (int k = 0; k < 4; ++k)
      centroid += row3(after.rest, after.tets(t, k)) / 4;
    const int parent = containing_tet(before, centroid);
    ASSERT_GE(parent, 0) << "tet " << t << " lies outside the mesh before the cut";
    EXPECT_EQ(after.labels(t), before.labels(parent)) << "tet " << t;
  }
  // Every reported change is a slot of the mesh, and every slot beyond the old ones is reported.
  ASSERT_TRUE(std::is_sorted(report.changed_tets.begin(), report.changed_tets.end()));
  for (int t = before.num_tets(); t < after.num_tets(); ++t)
    EXPECT_TRUE(std::binary_search(report.changed_tets.begin(), report.changed_tets.end(), t));
  for (int t = 0; t < before.num_tets(); ++t) {
    if (!std::binary_search(report.changed_tets.begin(), report.changed_tets.end(), t)) {
      EXPECT_EQ(after.tets.row(t), before.tets.row(t)) << "unreported change of tet " << t;
    }
  }
}

}  // namespace incise::sim::cut::testing
