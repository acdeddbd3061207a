#include "sim/mesh/cgal/anatomy.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <numbers>
#include <set>
#include <string>
#include <utility>

#include "mesh_checks.h"
#include "sim/mesh/mesh_quality.h"
#include "sim/solve/stable_time_step.h"

// The checks below recompute every property from the arrays (surface topology, volumes,
// distances, point-in-tet) rather than trusting the code under test.

namespace incise::sim {
namespace {

using testing::labelled_volume;

template <typename F>
auto timed(const char* name, F make) {
  const auto start = std::chrono::steady_clock::now();
  auto result = make();
  const std::chrono::duration<double> seconds = std::chrono::steady_clock::now() - start;
  std::printf("[figures] %s generated in %.2f s\n", name, seconds.count());
  return result;
}

const KneeAnatomy& knee() {
  static const KneeAnatomy k = timed("knee (default options)", [] { return make_knee({}); });
  return k;
}

const LiverAnatomy& liver() {
  static const LiverAnatomy l =
      timed("liver (default options)", [] { return make_liver_scene({}); });
  return l;
}

// Volume [m^3] enclosed by a closed triangle surface (divergence theorem); > 0 if outward.
Real enclosed_volume(const SurfaceMesh& s) {
  Real v = 0;
  for (Eigen::Index f = 0; f < s.triangles.rows(); ++f) {
    const Vec3 a = row3(s.vertices, s.triangles(f, 0));
    const Vec3 b = row3(s.vertices, s.triangles(f, 1));
    const Vec3 c = row3(s.vertices, s.triangles(f, 2));
    v += a.dot(b.cross(c)) / 6;
  }
  return v;
}

Real surface_area(const SurfaceMesh& s) {
  Real area = 0;
  for (Eigen::Index f = 0; f < s.triangles.rows(); ++f) {
    const Vec3 a = row3(s.vertices, s.triangles(f, 0));
    area += (row3(s.vertices, s.triangles(f, 1)) - a)
                .cross(row3(s.vertices, s.triangles(f, 2)) - a)
                .norm() /
            2;
  }
  return area;
}

// Closed, consistently oriented, manifold and of sphere topology: every directed edge appears
// once and its reverse once (so every edge has exactly two triangles, oriented alike), every
// vertex is used, and V - E + F = 2.
void expect_closed_sphere(const SurfaceMesh& s, const char* name) {
  std::map<std::pair<int, int>, int> directed;
  std::vector<int> used(static_cast<std::size_t>(s.vertices.rows()), 0);
  for (Eigen::Index f = 0; f < s.triangles.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      ++directed[{s.triangles(f, k), s.triangles(f, (k + 1) % 3)}];
      ++used[static_cast<std::size_t>(s.triangles(f, k))];
    }
  }
  int bad = 0;
  for (const auto& [edge, count] : directed) {
    const auto reverse = directed.find({edge.second, edge.first});
    if (count != 1 || reverse == directed.end() || reverse->second != 1) ++bad;
  }
  EXPECT_EQ(bad, 0) << name << ": edges not shared by exactly two consistently oriented faces";
  EXPECT_EQ(std::count(used.begin(), used.end(), 0), 0) << name << ": unused vertices";
  const long V = s.vertices.rows(), E = static_cast<long>(directed.size()) / 2,
             F = s.triangles.rows();
  EXPECT_EQ(V - E + F, 2) << name << ": not a single closed sphere-like surface";
  EXPECT_GT(enclosed_volume(s), 0) << name << ": faces point inwards";
}

// The volume [m^3] of {implicit_value < 0}, by the midpoint rule on a grid of the given step.
Real implicit_volume(const EllipsoidBlend& shape, Real step) {
  const Box3 box = implicit_extent(shape);
  const Vec3i n = (box.sizes() / step).array().ceil().cast<int>();
  long inside = 0;
  for (int k = 0; k < n.z(); ++k)
    for (int j = 0; j < n.y(); ++j)
      for (int i = 0; i < n.x(); ++i) {
        const Vec3 p = box.min() + step * (Vec3(i, j, k) + Vec3::Constant(0.5));
        inside += implicit_value(shape, p) < 0 ? 1 : 0;
      }
  return static_cast<Real>(inside) * step * step * step;
}

Real segment_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Real s = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), Real(0), Real(1));
  return (p - a - s * (b - a)).norm();
}

// Distance [m] from p to the triangle (a, b, c): to the plane if p projects inside, else to the
// nearest edge.
Real triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = (b - a).cross(c - a);
  const Vec3 q = p - (p - a).dot(n) / n.squaredNorm() * n;
  const bool inside = (b - a).cross(q - a).dot(n) >= 0 && (c - b).cross(q - b).dot(n) >= 0 &&
                      (a - c).cross(q - c).dot(n) >= 0;
  if (inside) return (p - q).norm();
  return std::min(
      {segment_distance(p, a, b), segment_distance(p, b, c), segment_distance(p, c, a)});
}

// The boundary faces (3 node indices, unoriented) of the tets with label (any label if < 0):
// faces that exactly one such tet has.
std::vector<std::array<int, 3>> boundary_of(const TetMesh& mesh, int label) {
  std::map<std::array<int, 3>, int> count;
  for (int t = 0; t < mesh.num_tets(); ++t) {
    if (label >= 0 && mesh.labels[t] != label) continue;
    for (int skip = 0; skip < 4; ++skip) {
      std::array<int, 3> face;
      int m = 0;
      for (int k = 0; k < 4; ++k)
        if (k != skip) face[m++] = mesh.tets(t, k);
      std::sort(face.begin(), face.end());
      ++count[face];
    }
  }
  std::vector<std::array<int, 3>> faces;
  for (const auto& [face, c] : count)
    if (c == 1) faces.push_back(face);
  return faces;
}

Real distance_to_faces(const Vec3& p, const Points& x, const std::vector<std::array<int, 3>>& f) {
  Real d = 1e9;
  for (const auto& face : f)
    d = std::min(d, triangle_distance(p, row3(x, face[0]), row3(x, face[1]), row3(x, face[2])));
  return d;
}

// The label of the tet containing p (within round-off), or -1.
int label_of_tet_at(const TetMesh& mesh, const Vec3& p) {
  for (int t = 0; t < mesh.num_tets(); ++t) {
    const Vec3 a = row3(mesh.rest, mesh.tets(t, 0)), b = row3(mesh.rest, mesh.tets(t, 1));
    const Vec3 c = row3(mesh.rest, mesh.tets(t, 2)), d = row3(mesh.rest, mesh.tets(t, 3));
    const Real v = signed_volume(a, b, c, d), eps = -1e-12 * v;
    if (signed_volume(p, b, c, d) >= eps && signed_volume(a, p, c, d) >= eps &&
        signed_volume(a, b, p, d) >= eps && signed_volume(a, b, c, p) >= eps) {
      return mesh.labels[t];
    }
  }
  return -1;
}

std::vector<int> node_label(const TetMesh& mesh) {
  std::vector<int> label(static_cast<std::size_t>(mesh.num_nodes()), -1);
  for (int t = 0; t < mesh.num_tets(); ++t)
    for (int k = 0; k < 4; ++k)
      label[static_cast<std::size_t>(mesh.tets(t, k))] = mesh.labels[t];
  return label;
}

void expect_ascending_in_range(const std::vector<int>& nodes, int num_nodes) {
  ASSERT_FALSE(nodes.empty());
  EXPECT_TRUE(std::adjacent_find(nodes.begin(), nodes.end(), std::greater_equal<int>()) ==
              nodes.end());
  EXPECT_GE(nodes.front(), 0);
  EXPECT_LT(nodes.back(), num_nodes);
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "no error";
}

// ---------------------------------------------------------------------------------------------
// Knee

TEST(KneeAnatomy, BonesAreClosedOutwardSurfacesOfTheirImplicitShapes) {
  const KneeAnatomy& k = knee();
  const KneeOptions o;
  const std::pair<const char*, std::pair<const SurfaceMesh*, const EllipsoidBlend*>> bones[] = {
      {"femur", {&k.femur, &k.femur_shape}}, {"tibia", {&k.tibia, &k.tibia_shape}}};
  for (const auto& [name, bone] : bones) {
    const auto& [surface, shape] = bone;
    expect_closed_sphere(*surface, name);
    Real off = 0;
    for (Eigen::Index v = 0; v < surface->vertices.rows(); ++v)
      off = std::max(off, std::abs(implicit_value(*shape, row3(surface->vertices, v))));
    // Mesh_3 puts surface vertices on the surface to ~1e-5 of the bounds' diagonal (~0.2 m).
    EXPECT_LT(off, 1e-5) << name;
    const Real volume = enclosed_volume(*surface), area = surface_area(*surface);
    const Real step = 0.001, expected = implicit_volume(*shape, step);
    std::printf(
        "[figures] %s: %ld vertices, %ld triangles, volume %.6g m^3, implicit %.6g m^3, "
        "mean inset %.3g mm\n",
        name, static_cast<long>(surface->vertices.rows()),
        static_cast<long>(surface->triangles.rows()), volume, expected,
        1e3 * (expected - volume) / area);
    // The surface is inscribed within facet_distance = bone_facet_size / 5 of the implicit
    // surface; the grid's midpoint rule errs by far less than step / 4 per unit area.
    EXPECT_NEAR(volume, expected, area * (o.bone_facet_size / 5 + step / 4)) << name;
    EXPECT_LT(volume, expected) << name << ": an inscribed surface encloses less";
  }
}

TEST(KneeAnatomy, TissueLabelsKeepTheirSegmentedVolumes) {
  const KneeAnatomy& k = knee();
  for (int t = 0; t < k.tissue.num_tets(); ++t) {
    ASSERT_TRUE(k.tissue.labels[t] >= 1 && k.tissue.labels[t] <= 3) << "tet " << t;
  }
  testing::expect_valid(k.tissue, label_volume_extent(k.segmentation));
  std::printf("[figures] knee tissue: %d nodes, %d tets, voxels %d x %d x %d\n",
              k.tissue.num_nodes(), k.tissue.num_tets(), k.segmentation.dims.x(),
              k.segmentation.dims.y(), k.segmentation.dims.z());
  for (const int label : {kMedialMeniscusLabel, kLateralMeniscusLabel, kLigamentLabel}) {
    const Real mesh_volume = labelled_volume(k.tissue.rest, k.tissue.tets, k.tissue.labels, label);
    const Real voxels = voxel_volume_of(k.segmentation, label);
    const long tets = std::count(k.tissue.labels.begin(), k.tissue.labels.end(), label);
    std::printf("[figures] label %d: %ld tets, volume %.4g m^3, voxels %.4g m^3 (%+.1f%%)\n", label,
                tets, mesh_volume, voxels, 100 * (mesh_volume / voxels - 1));
    EXPECT_GT(tets, 50) << label;
    // 20% (measured 9-15% less at the default 2 mm cells): the tissues are only 2-9 voxels
    // thick, so the fraction of a voxel layer by which the smoothed voxel boundary (label_at) and
    // the inscribed mesh facets (facet distance one voxel, for the stable step: make_knee) fall
    // inside the voxels is a tenth of the volume or more. Never more than the voxels.
    EXPECT_NEAR(mesh_volume, voxels, 0.20 * voxels) << label;
    EXPECT_LT(mesh_volume, voxels) << label;
  }
}

// No slivers, and no tets so small that they set a step far below the cells' size: the smallest
// dihedral angle and the stable step of the stiffest tissue (the ligament's P-wave speed) on the
// default 2 mm cells (measured 13.4 degrees and 22.9 us; 12.0 degrees and 8.2 us at 3 mm cells
// when the facets followed the voxels to a third of one).
TEST(KneeAnatomy, TheTissueMeshHasNoSliversAndAStableStepOfTensOfMicroseconds) {
  const KneeAnatomy& k = knee();
  const QualitySummary q = summarize_quality(k.tissue.rest, k.tissue.tets);
  const Real min_dihedral_deg = q.min_dihedral.min * 180 / std::numbers::pi;
  const Real step = stable_time_step(k.tissue, 60000, 0.3, 1100);
  std::printf("[figures] knee tissue: smallest dihedral angle %.2f deg, stable step %.1f us\n",
              min_dihedral_deg, step * 1e6);
  EXPECT_GE(min_dihedral_deg, 10.0);
  EXPECT_EQ(q.num_inverted + q.num_degenerate, 0);
  EXPECT_GE(step, 15e-6);
}

TEST(KneeAnatomy, SoftTissueRestsAgainstButOutsideTheBones) {
  const KneeAnatomy& k = knee();
  const std::vector<int> label = node_label(k.tissue);
  std::map<int, Real> to_femur, to_tibia;  // smallest implicit value per tissue
  for (int n = 0; n < k.tissue.num_nodes(); ++n) {
    const int l = label[static_cast<std::size_t>(n)];
    const Vec3 p = row3(k.tissue.rest, n);
    to_femur.try_emplace(l, 1.0);
    to_tibia.try_emplace(l, 1.0);
    to_femur[l] = std::min(to_femur[l], implicit_value(k.femur_shape, p));
    to_tibia[l] = std::min(to_tibia[l], implicit_value(k.tibia_shape, p));
  }
  const Real h = k.segmentation.spacing.x();
  for (const int l : {kMedialMeniscusLabel, kLateralMeniscusLabel, kLigamentLabel}) {
    std::printf("[figures] label %d: closest node to femur %.3g mm, to tibia %.3g mm\n", l,
                1e3 * to_femur[l], 1e3 * to_tibia[l]);
    // No interpenetration at rest: every node stays outside both bones (gap >= 0). The
    // implicit value is ~ the distance; the bone meshes lie inside it (inscribed).
    EXPECT_GE(to_femur[l], 0) << l;
    EXPECT_GE(to_tibia[l], 0) << l;
    // ... and each tissue touches what holds it: the menisci lie on the plateau and under the
    // condyles, the ligament reaches both bones (within the clearance plus one voxel).
    EXPECT_LT(to_tibia[l], k.bone_clearance + h) << l;
    EXPECT_LT(to_femur[l], k.bone_clearance + h) << l;
  }
}

TEST(KneeAnatomy, HeldNodesAreTheHornsAndTheLigamentEnds) {
  const KneeAnatomy& k = knee();
  expect_ascending_in_range(k.held_nodes, k.tissue.num_nodes());
  const std::vector<int> label = node_label(k.tissue);
  const Vec3 medial = find_landmark(k.landmarks, "medial_tibial_plateau").position;
  const Vec3 lateral = find_landmark(k.landmarks, "lateral_tibial_plateau").position;
  // Per tissue: held nodes anterior / posterior of the compartment centre, near femur / tibia.
  std::map<int, int> anterior, posterior, near_femur, near_tibia;
  const Real near = k.bone_clearance + k.segmentation.spacing.x();
  for (const int n : k.held_nodes) {
    const int l = label[static_cast<std::size_t>(n)];
    const Vec3 p = row3(k.tissue.rest, n);
    const Real cy = l == kMedialMeniscusLabel ? medial.y() : lateral.y();
    (p.y() > cy ? anterior : posterior)[l] += 1;
    near_femur[l] += implicit_value(k.femur_shape, p) <= near ? 1 : 0;
    near_tibia[l] += implicit_value(k.tibia_shape, p) <= near ? 1 : 0;
    if (l != kLigamentLabel) {
      EXPECT_LE(implicit_value(k.tibia_shape, p), near) << "node " << n;
    }
  }
  for (const int l : {kMedialMeniscusLabel, kLateralMeniscusLabel}) {
    std::printf("[figures] label %d held: %d anterior horn, %d posterior horn\n", l, anterior[l],
                posterior[l]);
    EXPECT_GE(anterior[l], 3) << l;
    EXPECT_GE(posterior[l], 3) << l;
  }
  std::printf("[figures] ligament held: %d at the femur, %d at the tibia, %zu held in all\n",
              near_femur[kLigamentLabel], near_tibia[kLigamentLabel], k.held_nodes.size());
  EXPECT_GE(near_femur[kLigamentLabel], 3);
  EXPECT_GE(near_tibia[kLigamentLabel], 3);
  EXPECT_EQ(k.protected_labels, std::vector<int>{kLigamentLabel});
}

TEST(KneeAnatomy, LandmarksLieOnTheirStructures) {
  const KneeAnatomy& k = knee();
  for (const char* side : {"medial", "lateral"}) {
    const std::string s = side;
    const Vec3 condyle = find_landmark(k.landmarks, s + "_femoral_condyle").position;
    const Vec3 plateau = find_landmark(k.landmarks, s + "_tibial_plateau").position;
    EXPECT_NEAR(implicit_value(k.femur_shape, condyle), 0, 1e-9) << s;
    EXPECT_NEAR(implicit_value(k.tibia_shape, plateau), 0, 1e-9) << s;
    EXPECT_GT(condyle.z(), plateau.z()) << s << ": the condyle sits on its plateau";
    EXPECT_EQ(s == "medial", condyle.x() < 0) << s << ": medial is -x";
    const int l = s == "medial" ? kMedialMeniscusLabel : kLateralMeniscusLabel;
    const Vec3 front = find_landmark(k.landmarks, s + "_meniscus_anterior_horn").position;
    const Vec3 back = find_landmark(k.landmarks, s + "_meniscus_posterior_horn").position;
    EXPECT_EQ(label_at(k.segmentation, front), l) << s;
    EXPECT_EQ(label_at(k.segmentation, back), l) << s;
    EXPECT_EQ(label_of_tet_at(k.tissue, front), l) << s;
    EXPECT_EQ(label_of_tet_at(k.tissue, back), l) << s;
    EXPECT_GT(front.y(), back.y()) << s << ": y is anterior";
  }
  const Vec3 acl = find_landmark(k.landmarks, "acl_midpoint").position;
  EXPECT_EQ(label_of_tet_at(k.tissue, acl), kLigamentLabel);
  EXPECT_THROW(find_landmark(k.landmarks, "patella"), std::out_of_range);
}

TEST(KneeAnatomy, PortalsAreOutsideAndAimIntoTheJoint) {
  const KneeAnatomy& k = knee();
  ASSERT_EQ(k.portals.size(), 2u);
  for (const Portal& portal : k.portals) {
    EXPECT_NEAR(portal.direction.norm(), 1, 1e-12) << portal.name;
    // 5 mm into the portal's direction is still free space: the instrument can enter.
    for (const Real s : {0.0, 0.005}) {
      const Vec3 p = portal.position + s * portal.direction;
      EXPECT_GT(implicit_value(k.femur_shape, p), 0) << portal.name;
      EXPECT_GT(implicit_value(k.tibia_shape, p), 0) << portal.name;
      EXPECT_EQ(label_at(k.segmentation, p), 0) << portal.name;
    }
    EXPECT_LT(portal.direction.y(), 0) << portal.name << ": pointing posteriorly, into the knee";
  }
  EXPECT_EQ(k.portals[0].name, "anterolateral");
  EXPECT_GT(k.portals[0].position.x(), 0);
  EXPECT_EQ(k.portals[1].name, "anteromedial");
  EXPECT_LT(k.portals[1].position.x(), 0);
}

TEST(KneeAnatomy, CutTargetLiesOnTheMedialMeniscusUpperSurface) {
  const KneeAnatomy& k = knee();
  ASSERT_GE(k.cut_target.size(), 2u);
  const auto faces = boundary_of(k.tissue, kMedialMeniscusLabel);
  Real length = 0;
  for (std::size_t i = 0; i < k.cut_target.size(); ++i) {
    const Vec3& p = k.cut_target[i];
    EXPECT_LT(distance_to_faces(p, k.tissue.rest, faces), 1e-9) << "point " << i;
    // Just below is medial meniscus, just above is outside it: the upper surface.
    EXPECT_EQ(label_of_tet_at(k.tissue, p - Vec3(0, 0, 2e-4)), kMedialMeniscusLabel) << i;
    EXPECT_NE(label_of_tet_at(k.tissue, p + Vec3(0, 0, 2e-4)), kMedialMeniscusLabel) << i;
    if (i > 0) length += (p - k.cut_target[i - 1]).norm();
  }
  std::printf("[figures] meniscus cut target: %zu points, %.2f mm long\n", k.cut_target.size(),
              1e3 * length);
  EXPECT_GT(length, 0.003);
}

TEST(KneeAnatomy, InvalidOptionsAreRejectedWithTheField) {
  const auto message = [](KneeOptions o) { return error_of([&] { make_knee(o); }); };
  KneeOptions o;
  o.voxel_size = 0;
  EXPECT_EQ(message(o), "knee options: voxel_size [m] = 0 is outside (0, 0.0015]");
  o = {};
  o.voxel_size = NAN;
  EXPECT_NE(message(o).find("voxel_size [m] = nan"), std::string::npos) << message(o);
  o = {};
  o.tissue_cell_size = 0.0005;
  EXPECT_EQ(message(o), "knee options: tissue_cell_size [m] = 0.0005 is outside [0.001, 0.004]");
  o = {};
  o.bone_facet_size = -1;
  EXPECT_EQ(message(o), "knee options: bone_facet_size [m] = -1 is outside (0, 0.02]");
  o = {};
  o.flexion_deg = 120;
  EXPECT_EQ(message(o), "knee options: flexion_deg = 120 is outside [0, 90]");
  EXPECT_EQ(error_of([] { check_knee_options({}); }), "no error");
}

TEST(KneeAnatomy, SameOptionsGiveTheSameMeshes) {
  KneeOptions o;  // coarse, to keep the test short
  o.voxel_size = 0.0015;
  o.tissue_cell_size = 0.003;
  o.bone_facet_size = 0.008;
  o.flexion_deg = 30;
  const KneeAnatomy a = timed("knee (coarse)", [&] { return make_knee(o); });
  const KneeAnatomy b = make_knee(o);
  EXPECT_EQ(a.femur.vertices, b.femur.vertices);
  EXPECT_EQ(a.femur.triangles, b.femur.triangles);
  EXPECT_EQ(a.tibia.vertices, b.tibia.vertices);
  EXPECT_EQ(a.tissue.rest, b.tissue.rest);
  EXPECT_EQ(a.tissue.tets, b.tissue.tets);
  EXPECT_EQ(a.tissue.labels, b.tissue.labels);
  EXPECT_EQ(a.held_nodes, b.held_nodes);
  EXPECT_EQ(a.cut_target, b.cut_target);
  // Flexion leans the femoral shaft back: 30 degrees against the default 10 move its top
  // posteriorly by about the shaft's length (6 cm) times sin 30 - sin 10 = 0.33.
  const auto top = [](const SurfaceMesh& s) {
    Eigen::Index i;
    s.vertices.col(2).maxCoeff(&i);
    return row3(s.vertices, static_cast<int>(i));
  };
  EXPECT_LT(top(a.femur).y(), top(knee().femur).y() - 0.015);
}

// ---------------------------------------------------------------------------------------------
// Liver

TEST(LiverScene, OrganIsHeldOnItsFlatSide) {
  const LiverAnatomy& l = liver();
  const LiverOptions o;
  // Surface nodes lie on the surface to ~1e-5 of the meshed bounds' diagonal (mesh_generation.h),
  // so those of the flat side may lie that much below the extent's bottom.
  const Box3 extent = implicit_extent(l.shape);
  const Vec3 pad = Vec3::Constant(2e-5 * extent.diagonal().norm());
  testing::expect_valid(l.organ, Box3(extent.min() - pad, extent.max() + pad));
  expect_ascending_in_range(l.held_nodes, l.organ.num_nodes());
  std::set<int> boundary;
  for (const auto& face : boundary_of(l.organ, -1))
    boundary.insert(face.begin(), face.end());
  Box3 held_box;
  const Real band = 0.01 * o.length;  // the header's "within length / 100 of its plane"
  for (const int n : l.held_nodes) {
    EXPECT_TRUE(boundary.count(n)) << "held node " << n << " is not on the surface";
    EXPECT_GE(l.organ.rest(n, 2), l.shape.flat_side_z - 1e-5 * o.length) << n;
    EXPECT_LE(l.organ.rest(n, 2), l.shape.flat_side_z + band) << n;
    held_box.extend(row3(l.organ.rest, n));
  }
  // ... and all of them: no surface node in the band is left free.
  int in_band = 0;
  for (const int n : boundary)
    in_band += l.organ.rest(n, 2) <= l.shape.flat_side_z + band ? 1 : 0;
  EXPECT_EQ(in_band, static_cast<int>(l.held_nodes.size()));
  std::printf(
      "[figures] liver: %d nodes, %d tets, %zu surface nodes, %zu held, held span %.3g x "
      "%.3g m\n",
      l.organ.num_nodes(), l.organ.num_tets(), boundary.size(), l.held_nodes.size(),
      held_box.sizes().x(), held_box.sizes().y());
  // The held nodes cover the flat side, not a corner of it.
  EXPECT_GT(held_box.sizes().x(), 0.3 * o.length);
}

TEST(LiverScene, CutLineLiesOnTheUpperSurface) {
  const LiverAnatomy& l = liver();
  const LiverOptions o;
  ASSERT_EQ(static_cast<int>(l.cut_line.size()), o.cut_points);
  const auto faces = boundary_of(l.organ, -1);
  for (std::size_t i = 0; i < l.cut_line.size(); ++i) {
    const Vec3& p = l.cut_line[i];
    EXPECT_LT(distance_to_faces(p, l.organ.rest, faces), 1e-9) << i;
    // On the mesh surface, hence within its facet distance (cell_size / 8) of the organ's.
    EXPECT_LT(std::abs(implicit_value(l.shape, p)), o.cell_size / 8) << i;
    EXPECT_GT(implicit_value(l.shape, p + Vec3(0, 0, 0.002)), 0) << i << ": upper surface";
    EXPECT_LT(implicit_value(l.shape, p - Vec3(0, 0, 0.004)), 0) << i << ": upper surface";
    EXPECT_GT((p - l.gallbladder_centre).norm(), l.gallbladder_radius) << i;
  }
  const Vec3 span = l.cut_line.back() - l.cut_line.front();
  EXPECT_NEAR(span.head<2>().norm(), o.cut_length, 1e-12);
  EXPECT_EQ(find_landmark(l.landmarks, "cut_start").position, l.cut_line.front());
  EXPECT_EQ(find_landmark(l.landmarks, "cut_end").position, l.cut_line.back());
  for (const char* lobe : {"right_lobe", "left_lobe", "caudate_lobe"}) {
    EXPECT_LT(implicit_value(l.shape, find_landmark(l.landmarks, lobe).position), 0) << lobe;
  }
}

TEST(LiverScene, GallbladderBedIsLabelledAndProtected) {
  const LiverAnatomy& l = liver();
  int bed = 0;
  for (int t = 0; t < l.organ.num_tets(); ++t) {
    Vec3 centroid = Vec3::Zero();
    for (int k = 0; k < 4; ++k)
      centroid += row3(l.organ.rest, l.organ.tets(t, k)) / 4;
    const bool in_ball = (centroid - l.gallbladder_centre).norm() < l.gallbladder_radius;
    EXPECT_EQ(l.organ.labels[t], in_ball ? kGallbladderBedLabel : kLiverLabel) << t;
    bed += in_ball ? 1 : 0;
  }
  std::printf("[figures] liver: %d gallbladder-bed tets\n", bed);
  EXPECT_GT(bed, 0);
  EXPECT_EQ(l.protected_labels, std::vector<int>{kGallbladderBedLabel});
  EXPECT_NEAR(find_landmark(l.landmarks, "gallbladder").position.z(), l.shape.flat_side_z, 1e-12);
}

TEST(LiverScene, InvalidOptionsAreRejectedWithTheField) {
  const auto message = [](LiverOptions o) { return error_of([&] { make_liver_scene(o); }); };
  LiverOptions o;
  o.cell_size = 0;
  EXPECT_EQ(message(o), "liver options: cell_size [m] = 0 is outside [0.00266667, 0.032]");
  o = {};
  o.length = 2;
  EXPECT_EQ(message(o), "liver options: length [m] = 2 is outside [0.05, 0.5]");
  o = {};
  o.cut_length = 0.1;
  EXPECT_EQ(message(o), "liver options: cut_length [m] = 0.1 is outside (0, 0.08]");
  o = {};
  o.cut_points = 1;
  EXPECT_EQ(message(o), "liver options: cut_points = 1 is outside [2, 1000]");
  o = {};
  o.centre.x() = INFINITY;
  EXPECT_EQ(message(o), "liver options: centre is not finite");
}

TEST(LiverScene, SameOptionsGiveTheSameMesh) {
  LiverOptions o;
  o.cell_size = 0.015;
  o.centre = Vec3(0.1, -0.2, 0.3);
  const LiverAnatomy a = make_liver_scene(o);
  const LiverAnatomy b = make_liver_scene(o);
  EXPECT_EQ(a.organ.rest, b.organ.rest);
  EXPECT_EQ(a.organ.tets, b.organ.tets);
  EXPECT_EQ(a.organ.labels, b.organ.labels);
  EXPECT_EQ(a.held_nodes, b.held_nodes);
  EXPECT_EQ(a.cut_line, b.cut_line);
}

}  // namespace
}  // namespace incise::sim
