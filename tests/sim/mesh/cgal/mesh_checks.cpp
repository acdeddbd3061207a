#include "mesh_checks.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include <gtest/gtest.h>

#include "sim/mesh/tet_adjacency.h"
#include "sim/mesh/tet_mesh.h"

namespace incise::sim::testing {

Real min_dihedral_angle_deg(const Points& points, const Tets& tets) {
  Real smallest = 180;
  for (Eigen::Index t = 0; t < tets.rows(); ++t) {
    // Outward normal of the face opposite each local node (kTetFaces is outward for positive tets).
    Vec3 normal[4];
    for (int k = 0; k < 4; ++k) {
      const Vec3 a = row3(points, tets(t, kTetFaces[k][0]));
      const Vec3 b = row3(points, tets(t, kTetFaces[k][1]));
      const Vec3 c = row3(points, tets(t, kTetFaces[k][2]));
      normal[k] = (b - a).cross(c - a).normalized();
    }
    // The edge (i, j) lies in the faces opposite the other two nodes k, l; its interior angle is
    // pi minus the angle between their outward normals.
    for (int k = 0; k < 4; ++k) {
      for (int l = k + 1; l < 4; ++l) {
        const Real c = std::clamp(normal[k].dot(normal[l]), Real(-1), Real(1));
        smallest = std::min(smallest, 180 - std::acos(c) * 180 / std::numbers::pi);
      }
    }
  }
  return smallest;
}

int num_components(const Tets& tets) {
  const Tets neighbours = face_neighbours(tets);
  std::vector<int> component(static_cast<std::size_t>(tets.rows()), -1);
  int count = 0;
  std::vector<int> stack;
  for (int seed = 0; seed < tets.rows(); ++seed) {
    if (component[seed] >= 0) continue;
    component[seed] = count;
    stack.push_back(seed);
    while (!stack.empty()) {
      const int t = stack.back();
      stack.pop_back();
      for (int k = 0; k < 4; ++k) {
        const int n = neighbours(t, k);
        if (n >= 0 && component[n] < 0) {
          component[n] = count;
          stack.push_back(n);
        }
      }
    }
    ++count;
  }
  return count;
}

std::vector<int> boundary_nodes(const Tets& tets) {
  const Triangles faces = boundary_faces(tets);
  std::vector<int> nodes(faces.data(), faces.data() + faces.size());
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  return nodes;
}

Real labelled_volume(const Points& points, const Tets& tets, const Eigen::VectorXi& labels,
                     int label) {
  Real sum = 0;
  for (Eigen::Index t = 0; t < tets.rows(); ++t) {
    if (labels[t] != label) continue;
    sum += signed_volume(row3(points, tets(t, 0)), row3(points, tets(t, 1)),
                         row3(points, tets(t, 2)), row3(points, tets(t, 3)));
  }
  return sum;
}

MeshingCriteria criteria(Real size, Real distance) {
  MeshingCriteria c;
  c.cell_size = size;
  c.facet_size = size;
  c.facet_distance = distance;
  return c;
}

Box3 box_around(const Vec3& centre, Real half) {
  return Box3(centre - Vec3::Constant(half), centre + Vec3::Constant(half));
}

void expect_valid(const TetMesh& mesh, const Box3& bounds) {
  ASSERT_GT(mesh.num_tets(), 0);
  const VecX volumes = tet_volumes(mesh.rest, mesh.tets);
  EXPECT_GT(volumes.minCoeff(), 0);
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    EXPECT_TRUE(bounds.contains(row3(mesh.rest, i))) << "node " << i;
  }
  EXPECT_EQ(mesh.x, mesh.rest);
  EXPECT_TRUE((mesh.v.array() == 0).all());
  EXPECT_GT(min_dihedral_angle_deg(mesh.rest, mesh.tets), kMinDihedralBound);
}

void print_figures(const char* name, const TetMesh& mesh, Real volume, Real reference) {
  std::printf(
      "[figures] %s: %d nodes, %d tets, volume %.6g (reference %.6g, error %+.3f%%), "
      "min dihedral %.2f deg\n",
      name, mesh.num_nodes(), mesh.num_tets(), volume, reference,
      100 * (volume - reference) / reference, min_dihedral_angle_deg(mesh.rest, mesh.tets));
}

}  // namespace incise::sim::testing
