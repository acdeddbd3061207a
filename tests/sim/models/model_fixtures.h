#pragma once
// Meshes, materials and models the model tests share.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "sim/mesh/tet_mesh.h"
#include "sim/models/model.h"

namespace incise::sim::testing {

struct NamedMesh {
  std::string name;
  TetMesh mesh;
};

// A 3x2x2-cell box with labels alternating 0, 1; a single right-corner tet; a sliver (four nearly
// coplanar, well spread nodes); a box with every node jittered (still positively oriented).
std::vector<NamedMesh> test_meshes();

// Two tissues (labels 0 and 1), damping beta > 0 so that the damping forces are exercised.
std::vector<ElementMaterial> test_materials(Real poisson_ratio = 0.45);

struct ModelFactory {
  std::string name;
  bool rotation_invariant;
  std::function<std::unique_ptr<Model>(const TetMesh&, const std::vector<ElementMaterial>&)> make;
};
// Every model: linear, corotational (QR), corotational_polar, corotational_nodal_pressure, stvk,
// neohookean, mss, mss with the volume term.
std::vector<ModelFactory> all_models();

// Internal forces of model at (x, v).
Points forces(Model& model, const Points& x, const Points& v);

// A random rotation (from a random unit quaternion).
Mat3 random_rotation(unsigned seed);
// #rows by 3 entries uniform in [-scale, scale].
Points random_points(Eigen::Index rows, Real scale, unsigned seed);
// Bounding box diagonal of the rest positions [m].
Real mesh_size(const TetMesh& mesh);
// The rest shape moved rigidly: x_i = rotation X_i + shift.
Points rigidly_moved(const Points& rest, const Mat3& rotation, const Vec3& shift);
// Flattened (3 #nodes) view helper.
VecX flat(const Points& p);

}  // namespace incise::sim::testing
