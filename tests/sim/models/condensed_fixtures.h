#pragma once
// The bodies the hybrid condensed model's tests and benchmark share: a box with a small
// operational block at the middle of its top face (where a tool would work).
#include <cmath>
#include <memory>
#include <vector>

#include "sim/mesh/box_mesher.h"
#include "sim/models/corotational_fem.h"
#include "sim/models/hybrid_condensed_model.h"
#include "sim/models/linear_fem.h"
#include "sim/models/tet_elements.h"
#include "tests/sim/models/model_fixtures.h"

namespace incise::sim::testing {

// A cube of edge `size` on cells^3 cells, labels 0 and 1 alternating per tet (two tissues).
inline TetMesh condensed_box(int cells, Real size = 0.04) {
  TetMesh mesh = make_box_mesh(Vec3::Constant(size), Vec3i::Constant(cells));
  for (int t = 0; t < mesh.num_tets(); ++t)
    mesh.labels(t) = t % 2;
  return mesh;
}

// Operational: the tets whose centroid is within `half_width` of the top face's centre in x and y
// and within `depth` of the top face.
inline std::vector<char> top_block(const TetMesh& mesh, Real half_width, Real depth) {
  const Vec3 top = mesh.rest.colwise().maxCoeff().transpose();
  std::vector<char> operational(static_cast<std::size_t>(mesh.num_tets()), 0);
  for (int t = 0; t < mesh.num_tets(); ++t) {
    Vec3 centroid = Vec3::Zero();
    for (int a = 0; a < 4; ++a)
      centroid += row3(mesh.rest, mesh.tets(t, a)) / 4;
    const bool inside = std::abs(centroid.x() - top.x() / 2) < half_width &&
                        std::abs(centroid.y() - top.y() / 2) < half_width &&
                        centroid.z() > top.z() - depth;
    operational[static_cast<std::size_t>(t)] = inside ? 1 : 0;
  }
  return operational;
}

// Two soft tissues [Pa, -, kg/m^3, s]; the same damping beta for both unless told.
inline std::vector<ElementMaterial> condensed_materials(Real beta = 1e-3, Real beta_1 = -1) {
  return {{3e4, 0.45, 1000, beta}, {6e4, 0.40, 1100, beta_1 < 0 ? beta : beta_1}};
}

inline std::unique_ptr<Model> make_linear(const TetMesh& mesh,
                                          const std::vector<ElementMaterial>& materials) {
  return std::make_unique<LinearFem>(mesh, materials);
}

inline std::unique_ptr<Model> make_corotational(const TetMesh& mesh,
                                                const std::vector<ElementMaterial>& materials) {
  return std::make_unique<CorotationalFem>(mesh, materials, RotationExtraction::polar);
}

// #rows by 3 entries uniform in [-scale, scale], reproducible from seed.
inline Points random_displacements(Eigen::Index rows, Real scale, unsigned seed) {
  return random_points(rows, scale, seed);
}

// A #nodes by 3 array as one vector of 3 #nodes (node i's x, y, z at 3i, 3i+1, 3i+2).
inline VecX flatten(const Points& p) {
  return Eigen::Map<const VecX>(p.data(), p.size());
}

}  // namespace incise::sim::testing
