#include "sim/mesh/cgal/mesh_generation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <numbers>
#include <stdexcept>
#include <string>

#include "mesh_checks.h"

namespace incise::sim {
namespace {

using testing::boundary_nodes;
using testing::box_around;
using testing::criteria;
using testing::expect_valid;
using testing::num_components;
using testing::print_figures;

constexpr Real kPi = std::numbers::pi;

// The largest |implicit_value| over the boundary nodes [m].
Real max_boundary_offset(const ImplicitShape& shape, const TetMesh& mesh) {
  Real worst = 0;
  for (int i : boundary_nodes(mesh.tets)) {
    worst = std::max(worst, std::abs(implicit_value(shape, row3(mesh.rest, i))));
  }
  return worst;
}

TEST(MeshImplicit, SphereVolumeConvergesFromBelow) {
  const Sphere sphere{Vec3(0.01, -0.02, 0.03), 0.05};
  const Box3 bounds = box_around(sphere.centre, 0.06);
  const Real exact = 4 * kPi / 3 * std::pow(sphere.radius, 3);
  Real previous_error = 1;
  for (const auto& [size, distance] : {std::pair{0.05 / 2.5, 0.05 / 40}, {0.05 / 5, 0.05 / 100}}) {
    const MeshingCriteria c = criteria(size, distance);
    const TetMesh mesh = mesh_implicit(sphere, bounds, c);
    expect_valid(mesh, bounds);
    EXPECT_TRUE((mesh.labels.array() == 1).all());
    const Real volume = total_volume(mesh.rest, mesh.tets);
    print_figures("sphere", mesh, volume, exact);
    // Boundary vertices lie on the sphere, so the mesh is inscribed: its volume is below.
    EXPECT_LT(volume, exact);
    const Real error = (exact - volume) / exact;
    EXPECT_LT(error, previous_error);
    previous_error = error;
    EXPECT_LT(max_boundary_offset(sphere, mesh), 2 * c.facet_distance);
    for (int i = 0; i < mesh.num_nodes(); ++i) {
      EXPECT_LT(implicit_value(sphere, row3(mesh.rest, i)), 2 * c.facet_distance);
    }
  }
  EXPECT_LT(previous_error, 0.03);  // within 3% at size r / 5
}

TEST(MeshImplicit, EllipsoidVolumeFromBelow) {
  const Ellipsoid ellipsoid{Vec3(0, 0, 0), Vec3(0.06, 0.04, 0.03)};
  const Box3 bounds = box_around(ellipsoid.centre, 0.07);
  const MeshingCriteria c = criteria(0.006, 0.0005);
  const TetMesh mesh = mesh_implicit(ellipsoid, bounds, c);
  expect_valid(mesh, bounds);
  const Real exact = 4 * kPi / 3 * ellipsoid.radii.prod();
  const Real volume = total_volume(mesh.rest, mesh.tets);
  print_figures("ellipsoid", mesh, volume, exact);
  EXPECT_LT(volume, exact);
  EXPECT_GT(volume, 0.97 * exact);
  EXPECT_LT(max_boundary_offset(ellipsoid, mesh), 2 * c.facet_distance);
}

TEST(MeshImplicit, LiverLikeOrganIsOneBodyBetweenItsLargestLobeAndAllLobes) {
  const LobedOrgan organ = liver_like_organ(Vec3(0, 0, 0), 0.2);
  const Box3 bounds = box_around(Vec3::Zero(), 0.15);
  const MeshingCriteria c = criteria(0.01, 0.001);
  const TetMesh mesh = mesh_implicit(organ, bounds, c);
  expect_valid(mesh, bounds);
  EXPECT_EQ(num_components(mesh.tets), 1);
  Real largest = 0;
  Real sum = 0;
  for (const Ellipsoid& lobe : organ.lobes.parts) {
    const Real v = 4 * kPi / 3 * lobe.radii.prod();
    largest = std::max(largest, v);
    sum += v;
  }
  const Real volume = total_volume(mesh.rest, mesh.tets);
  print_figures("organ (reference = largest lobe)", mesh, volume, largest);
  std::printf("[figures] organ: sum of lobes %.6g\n", sum);
  EXPECT_GT(volume, largest);
  EXPECT_LT(volume, sum);
  EXPECT_LT(max_boundary_offset(organ, mesh), 2 * c.facet_distance);
  // The flat side is meshed flat: nodes reach down to it and no further.
  Real lowest = 1;
  for (int i = 0; i < mesh.num_nodes(); ++i)
    lowest = std::min(lowest, mesh.rest(i, 2));
  EXPECT_GT(lowest, organ.flat_side_z - 2 * c.facet_distance);
  EXPECT_LT(lowest, organ.flat_side_z + 2 * c.facet_distance);
}

TEST(MeshImplicit, SameInputGivesTheSameMesh) {
  const Sphere sphere{Vec3(0, 0, 0), 0.05};
  const Box3 bounds = box_around(sphere.centre, 0.06);
  const TetMesh a = mesh_implicit(sphere, bounds, criteria(0.02, 0.002));
  const TetMesh b = mesh_implicit(sphere, bounds, criteria(0.02, 0.002));
  EXPECT_EQ(a.rest, b.rest);
  EXPECT_EQ(a.tets, b.tets);
}

// A cube of tissue 1 holding a ball of tissue 2, in a volume with an empty (0) border.
TEST(MeshImplicit, SeparateOffCentreComponentsAreAllMeshed) {
  // Two small bodies in opposite corners of large bounds: rays from the bounds' centre (CGAL's
  // own way to find a first surface) rarely reach them; the seeding grid finds both.
  const Ellipsoid a{Vec3(0.6, 0.6, 0.6), Vec3(0.05, 0.04, 0.03)};
  const Ellipsoid b{Vec3(-0.6, 0.5, -0.6), Vec3(0.04, 0.04, 0.04)};
  const EllipsoidBlend pair{{a, b}, 0.005};
  const Box3 bounds = box_around(Vec3::Zero(), 1);
  const MeshingCriteria c = criteria(0.01, 0.001);
  const TetMesh mesh = mesh_implicit(pair, bounds, c);
  expect_valid(mesh, bounds);
  EXPECT_EQ(num_components(mesh.tets), 2);
  const Real exact = 4 * kPi / 3 * (a.radii.prod() + b.radii.prod());
  const Real volume = total_volume(mesh.rest, mesh.tets);
  print_figures("two separate ellipsoids", mesh, volume, exact);
  EXPECT_LT(volume, exact);
  EXPECT_GT(volume, 0.95 * exact);
}

TEST(MeshImplicit, ShapeTooSmallForTheCriteriaIsARuntimeError) {
  const Sphere speck{Vec3(0.8, 0.8, 0.8), 1e-3};
  try {
    const TetMesh mesh = mesh_implicit(speck, box_around(Vec3::Zero(), 1), criteria(0.5, 0.05));
    ADD_FAILURE() << "expected a runtime_error, got " << mesh.num_tets() << " tets";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("too small"), std::string::npos) << e.what();
  }
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "no error";
}

TEST(MeshGeneration, InvalidCriteriaAreRejectedWithTheField) {
  const Sphere sphere{Vec3::Zero(), 1};
  const Box3 bounds = box_around(Vec3::Zero(), 2);
  const std::map<std::string, MeshingCriteria> cases = {
      {"cell_size",
       [] {
         auto c = criteria(0.5, 0.1);
         c.cell_size = 0;
         return c;
       }()},
      {"facet_size",
       [] {
         auto c = criteria(0.5, 0.1);
         c.facet_size = NAN;
         return c;
       }()},
      {"facet_distance",
       [] {
         auto c = criteria(0.5, 0.1);
         c.facet_distance = -1;
         return c;
       }()},
      {"facet_angle_deg",
       [] {
         auto c = criteria(0.5, 0.1);
         c.facet_angle_deg = 35;
         return c;
       }()},
      {"cell_radius_edge_ratio",
       [] {
         auto c = criteria(0.5, 0.1);
         c.cell_radius_edge_ratio = 1.5;
         return c;
       }()},
  };
  for (const auto& [field, c] : cases) {
    EXPECT_NE(error_of([&] { mesh_implicit(sphere, bounds, c); }).find(field), std::string::npos)
        << field;
  }
  MeshingCriteria unset;
  EXPECT_NE(error_of([&] { mesh_implicit(sphere, bounds, unset); }).find("cell_size"),
            std::string::npos);
  EXPECT_NE(error_of([&] { mesh_implicit(sphere, bounds, criteria(1e-4, 1e-5)); }).find("coarsen"),
            std::string::npos);
}

TEST(MeshGeneration, InvalidShapesBoundsAndVolumesAreRejected) {
  const MeshingCriteria c = criteria(0.5, 0.1);
  EXPECT_NE(error_of([&] {
              mesh_implicit(Sphere{Vec3::Zero(), 1}, box_around(Vec3(0.5, 0, 0), 1.2), c);
            }).find("extent"),
            std::string::npos);
  EXPECT_NE(error_of([&] {
              mesh_implicit(Sphere{Vec3::Zero(), -1}, box_around(Vec3::Zero(), 2), c);
            }).find("radius"),
            std::string::npos);
  EXPECT_NE(error_of([&] {
              mesh_implicit(Sphere{Vec3::Zero(), 1}, Box3(), c);
            }).find("bounds"),
            std::string::npos);
  LabelVolume empty{Vec3i(2, 2, 2), Vec3::Constant(1), Vec3::Zero(),
                    std::vector<std::uint8_t>(8, 0)};
  EXPECT_NE(error_of([&] { mesh_labelled_volume(empty, c); }).find("no tissue"), std::string::npos);
}

}  // namespace
}  // namespace incise::sim
