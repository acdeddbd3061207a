// Progressive cuts (sim/cut/progressive_cutter.h): a blade moved frame by frame through a box
// mesh; after every frame the mesh is valid (positive tets in rest and current positions, rest
// volume kept, conforming with a closed manifold boundary, no orphan node), the temporary crack is
// on the blade's surface, and at the end the parts have the closed-form volumes of the one-shot
// cut of the same plane.

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "cut_checks.h"
#include "sim/cut/progressive_cutter.h"
#include "sim/mesh/box_mesher.h"

namespace incise::sim::cut {
namespace {

using testing::boundary_problem;
using testing::min_volume;
using testing::tet_components;

// Every node is used by some tet.
bool no_orphan_nodes(const TetMesh& mesh) {
  std::vector<char> used(static_cast<std::size_t>(mesh.num_nodes()), 0);
  for (int t = 0; t < mesh.num_tets(); ++t) {
    for (int k = 0; k < 4; ++k)
      used[static_cast<std::size_t>(mesh.tets(t, k))] = 1;
  }
  return std::all_of(used.begin(), used.end(), [](char u) { return u != 0; });
}

void expect_valid(const TetMesh& mesh, Real volume) {
  ASSERT_EQ(mesh.x.rows(), mesh.num_nodes());
  ASSERT_EQ(mesh.labels.size(), mesh.num_tets());
  EXPECT_GT(min_volume(mesh.rest, mesh.tets), 0);
  EXPECT_GT(min_volume(mesh.x, mesh.tets), 0);
  EXPECT_NEAR(total_volume(mesh.rest, mesh.tets), volume, 1e-9 * volume);
  EXPECT_EQ(boundary_problem(mesh.tets), "");
  EXPECT_TRUE(no_orphan_nodes(mesh));
}

// A blade in the plane n . p = c, spanning the unit box along one in-plane direction, moved along
// the other (s from -2 to 2 is outside the box at both ends).
struct PlaneStroke {
  Vec3 centre, along, across;
  PlaneStroke(const Vec3& normal, Real c) {
    const Vec3 n = normal.normalized();
    centre = normal * c / normal.squaredNorm();
    along = n.cross(Vec3::UnitX()).normalized();
    across = n.cross(along);
  }
  Vec3 a(Real s) const { return centre + s * across - 1.5 * along; }
  Vec3 b(Real s) const { return centre + s * across + 1.5 * along; }
};

Real below_volume(const Vec3& n, Real c) {
  return (c - n.y() / 2 - n.z() / 2) / n.x();
}

// Volumes of the components, the one holding node 0 first.
std::vector<Real> part_volumes(const TetMesh& mesh) {
  int count = 0;
  const std::vector<int> component = tet_components(mesh.tets, &count);
  std::vector<Real> volume(static_cast<std::size_t>(count), 0);
  const VecX volumes = tet_volumes(mesh.rest, mesh.tets);
  int origin = 0;
  for (int t = 0; t < mesh.num_tets(); ++t) {
    volume[static_cast<std::size_t>(component[static_cast<std::size_t>(t)])] += volumes(t);
    for (int k = 0; k < 4; ++k) {
      if (mesh.tets(t, k) == 0) origin = component[static_cast<std::size_t>(t)];
    }
  }
  std::swap(volume[0], volume[static_cast<std::size_t>(origin)]);
  return volume;
}

TEST(ProgressiveCutter, ThroughCutIsValidEveryFrameAndEndsAsTheOneShotCut) {
  const Vec3 n(1, 0.3, 0.2);
  const Real c = 0.5375;  // crossings away from nodes (see cut_mesh_test): nothing snaps
  const CutOptions options{0.01};
  TetMesh mesh = make_box_mesh({1, 1, 1}, {4, 4, 4});
  const Real volume = total_volume(mesh.rest, mesh.tets);
  ProgressiveCutter cutter(mesh, options);
  const PlaneStroke stroke(n, c);
  const int frames = 64;
  int frames_inside = 0;
  Real committed_area = 0;  // of the committed crack faces, both sides
  for (int f = 0; f <= frames; ++f) {
    const Real s = -2 + 4.0 * f / frames;
    const Tets previous = mesh.tets;
    const FrameReport& report = cutter.update(stroke.a(s), stroke.b(s));
    SCOPED_TRACE("frame " + std::to_string(f));
    expect_valid(mesh, volume);
    // The committed crack faces, in mesh nodes, lie on the plane (no deformation: rest = x).
    ASSERT_EQ(report.committed_crack_face_nodes.rows(), report.committed_crack_faces);
    ASSERT_EQ(report.committed_crack_face_labels.size(),
              static_cast<std::size_t>(report.committed_crack_faces));
    for (Eigen::Index r = 0; r < report.committed_crack_face_nodes.rows(); ++r) {
      std::array<Vec3, 3> p;
      for (int k = 0; k < 3; ++k) {
        p[static_cast<std::size_t>(k)] = row3(mesh.rest, report.committed_crack_face_nodes(r, k));
        EXPECT_NEAR(n.normalized().dot(p[static_cast<std::size_t>(k)]), c / n.norm(), 1e-9);
      }
      committed_area += 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).norm();
    }
    EXPECT_EQ(mesh.num_nodes(), cutter.committed_nodes() + report.temporary_nodes);
    if (report.front_tets > 0) {
      ++frames_inside;
      // The blade is inside: the crack shows up to it, on the plane (a centre or pierce point is
      // kept kFrontMargin inside its tet or face: moved by at most 4 kFrontMargin times the
      // longest edge, sqrt(3) / 4).
      EXPECT_GT(report.temporary_crack_faces.rows(), 0);
      for (Eigen::Index r = 0; r < report.temporary_crack_faces.rows(); ++r) {
        for (int k = 0; k < 3; ++k) {
          const Vec3 p = row3(mesh.x, report.temporary_crack_faces(r, k));
          EXPECT_LE(std::abs(n.normalized().dot(p) - c / n.norm()),
                    4 * kFrontMargin * std::sqrt(3.0) / 4);
        }
      }
    }
    // A model can follow: every slot whose row differs from the previous frame's, or is new, is
    // reported, and only existing slots are.
    ASSERT_TRUE(std::is_sorted(report.changed_tets.begin(), report.changed_tets.end()));
    for (int t = 0; t < mesh.num_tets(); ++t) {
      const bool changed = t >= previous.rows() || mesh.tets.row(t) != previous.row(t);
      if (changed) {
        EXPECT_TRUE(std::binary_search(report.changed_tets.begin(), report.changed_tets.end(), t))
            << "slot " << t;
      }
    }
    for (int t : report.changed_tets)
      EXPECT_LT(t, mesh.num_tets());
    EXPECT_EQ(report.tets_before, static_cast<int>(previous.rows()));
  }
  EXPECT_GT(frames_inside, 10);
  cutter.end_stroke();
  expect_valid(mesh, volume);
  EXPECT_EQ(mesh.num_nodes(), cutter.committed_nodes());
  const std::vector<Real> parts = part_volumes(mesh);
  ASSERT_EQ(parts.size(), 2u);
  EXPECT_NEAR(parts[0], below_volume(n, c), 1e-12);
  EXPECT_NEAR(parts[1], 1 - below_volume(n, c), 1e-12);

  TetMesh one_shot = make_box_mesh({1, 1, 1}, {4, 4, 4});
  const CutReport whole = cut_mesh(one_shot, testing::plane_blade(stroke.centre, n, 3), options);
  const std::vector<Real> expected = part_volumes(one_shot);
  ASSERT_EQ(expected.size(), 2u);
  EXPECT_NEAR(parts[0], expected[0], 1e-12);
  // The frames' committed crack faces add up to the one-shot cut's.
  Real whole_area = 0;
  for (Eigen::Index r = 0; r < whole.crack_faces.rows(); ++r) {
    const Vec3 a = row3(one_shot.rest, whole.crack_faces(r, 0));
    whole_area += 0.5 * (row3(one_shot.rest, whole.crack_faces(r, 1)) - a)
                            .cross(row3(one_shot.rest, whole.crack_faces(r, 2)) - a)
                            .norm();
  }
  EXPECT_GT(whole_area, 0);
  EXPECT_NEAR(committed_area, whole_area, 1e-9 * whole_area);
}

TEST(ProgressiveCutter, BackAndForthInsideLeavesNoTemporaryNodeAndOneBody) {
  TetMesh mesh = testing::jittered_box({1, 1, 1}, {5, 5, 5}, 0.2, 3);
  const Real volume = total_volume(mesh.rest, mesh.tets);
  ProgressiveCutter cutter(mesh);
  const PlaneStroke stroke({1, 0.2, -0.1}, 0.45);
  for (int f = 0; f <= 12; ++f) {
    const FrameReport& report = cutter.update(stroke.a(-1.2 + 0.1 * f), stroke.b(-1.2 + 0.1 * f));
    SCOPED_TRACE("frame " + std::to_string(f));
    expect_valid(mesh, volume);
    if (f == 12) {
      EXPECT_GT(report.front_tets, 0);
      EXPECT_GT(report.temporary_nodes, 0);
    }
  }
  // Back out the way it came (the surface swept backwards folds onto the one swept forwards),
  // then forward again: valid every frame, the temporary nodes always the last ones.
  for (int f = 11; f >= 0; --f) {
    const FrameReport& report = cutter.update(stroke.a(-1.2 + 0.1 * f), stroke.b(-1.2 + 0.1 * f));
    SCOPED_TRACE("back, frame " + std::to_string(f));
    expect_valid(mesh, volume);
    EXPECT_EQ(mesh.num_nodes(), cutter.committed_nodes() + report.temporary_nodes);
  }
  for (int f = 1; f <= 12; ++f) {
    const FrameReport& report = cutter.update(stroke.a(-1.2 + 0.1 * f), stroke.b(-1.2 + 0.1 * f));
    SCOPED_TRACE("forward again, frame " + std::to_string(f));
    expect_valid(mesh, volume);
    EXPECT_EQ(mesh.num_nodes(), cutter.committed_nodes() + report.temporary_nodes);
  }
  cutter.end_stroke();
  expect_valid(mesh, volume);
  EXPECT_EQ(mesh.num_nodes(), cutter.committed_nodes());
  EXPECT_EQ(mesh.num_tets(), cutter.committed_tets());
  int count = 0;
  tet_components(mesh.tets, &count);
  EXPECT_EQ(count, 1);  // the crack stops inside: still one body
}

TEST(ProgressiveCutter, CrossingStrokesCutTheBoxIntoFourParts) {
  TetMesh mesh = testing::jittered_box({1, 1, 1}, {4, 4, 4}, 0.2, 5);
  const Real volume = total_volume(mesh.rest, mesh.tets);
  ProgressiveCutter cutter(mesh);
  for (const auto& [normal, c] :
       {std::pair{Vec3(1, 0.3, 0.2), 0.537}, std::pair{Vec3(0.2, 1, -0.1), 0.55}}) {
    const PlaneStroke stroke(normal, c);
    for (int f = 0; f <= 40; ++f) {
      cutter.update(stroke.a(-2 + 0.1 * f), stroke.b(-2 + 0.1 * f));
      SCOPED_TRACE("frame " + std::to_string(f));
      expect_valid(mesh, volume);
    }
    cutter.end_stroke();
  }
  int count = 0;
  tet_components(mesh.tets, &count);
  EXPECT_EQ(count, 4);
}

// An affine motion of the whole mesh, different every frame: a rotation about a tilted axis, a
// stretch and a shift.
struct Motion {
  Mat3 a;
  Vec3 shift;
  explicit Motion(int frame) {
    const Real s = std::sin(0.7 * frame);
    a = Eigen::AngleAxis<Real>(0.4 * s, Vec3(1, 1, 0.5).normalized()).toRotationMatrix() *
        Vec3(1 + 0.1 * s, 1, 1 - 0.05 * s).asDiagonal();
    shift = Vec3(0.3 * s, -0.2 * s, 0.1);
  }
  Vec3 operator()(const Vec3& p) const { return a * p + shift; }
};

// BladeSpace::material: the blade is taken into the material through the tet at its tip, so a
// tissue moving under a blade that moves with it is cut exactly as a tissue at rest (the strip
// is embedded in the material). The same moving mesh cut in the current space would be crossed
// by the strip's old quads wherever the tissue has moved since.
TEST(ProgressiveCutter, InMaterialSpaceTheCutFollowsTheTissueAsItMoves) {
  TetMesh still = testing::jittered_box({1, 1, 1}, {4, 4, 4}, 0.2, 5);
  TetMesh moving = still;
  const Real volume = total_volume(still.rest, still.tets);
  ProgressiveCutter still_cutter(still, CutOptions{}, 0, BladeSpace::material);
  ProgressiveCutter moving_cutter(moving, CutOptions{}, 0, BladeSpace::material);
  const PlaneStroke stroke({1, 0.3, 0.2}, 0.537);
  int frames_inside = 0;
  for (int f = 0; f <= 40; ++f) {
    SCOPED_TRACE("frame " + std::to_string(f));
    const Motion motion(f);
    for (int i = 0; i < moving.num_nodes(); ++i)
      moving.x.row(i) = motion(row3(moving.rest, i)).transpose();
    const Real s = -2 + 0.1 * f;
    const FrameReport& report = still_cutter.update(stroke.a(s), stroke.b(s));
    const FrameReport& moved = moving_cutter.update(motion(stroke.a(s)), motion(stroke.b(s)));
    EXPECT_FALSE(report.blade_unmapped);
    EXPECT_FALSE(moved.blade_unmapped);
    frames_inside += moved.front_tets > 0 ? 1 : 0;
    expect_valid(moving, volume);
    ASSERT_EQ(moving.tets, still.tets);
    ASSERT_EQ(moving.num_nodes(), still.num_nodes());
    EXPECT_LT((moving.rest - still.rest).cwiseAbs().maxCoeff(), 1e-12);
    // New nodes are placed in the current configuration as the material they came from.
    for (int i = 0; i < moving.num_nodes(); ++i)
      EXPECT_LT((row3(moving.x, i) - motion(row3(moving.rest, i))).norm(), 1e-12) << i;
  }
  EXPECT_GT(frames_inside, 5);
  moving_cutter.end_stroke();
  int count = 0;
  tet_components(moving.tets, &count);
  EXPECT_EQ(count, 2);
}

// BladeSpace::material through a tangle: a tet the blade is in turned inside out (away from the
// tip's tet, which stays sound) holds the cut, and nothing changes; a tangle away from the blade
// does not; once the tangle is undone, the same pose cuts.
TEST(ProgressiveCutter, InMaterialSpaceTheCutWaitsWhileTheBladeIsInATangle) {
  TetMesh mesh = testing::jittered_box({1, 1, 1}, {4, 4, 4}, 0.2, 5);
  ProgressiveCutter cutter(mesh, CutOptions{}, 0, BladeSpace::material);
  const Real c = 0.537;
  const auto a = [&](Real y) { return Vec3(c, y, 0.2); };  // the tip, 0.8 deep
  const auto b = [&](Real y) { return Vec3(c, y, 1.5); };
  // Inverts a committed tet of `node` by mirroring the node through that tet's opposite face;
  // returns the node's old position. (The blade's temporary pieces are undone at the next frame.)
  const auto invert_at = [&](int node) {
    const Vec3 old = row3(mesh.x, node);
    for (int t = 0; t < cutter.committed_tets(); ++t) {
      int k = 0;
      while (k < 4 && mesh.tets(t, k) != node)
        ++k;
      if (k == 4) continue;
      const Vec3 p = row3(mesh.x, mesh.tets(t, (k + 1) % 4));
      const Vec3 q = row3(mesh.x, mesh.tets(t, (k + 2) % 4));
      const Vec3 r = row3(mesh.x, mesh.tets(t, (k + 3) % 4));
      const Vec3 n = (q - p).cross(r - p).normalized();
      mesh.x.row(node) = (old - 2 * n.dot(old - p) * n).transpose();
      break;
    }
    return old;
  };
  const auto nearest_node = [&](const Vec3& p) {
    int best = 0;
    for (int i = 1; i < cutter.committed_nodes(); ++i) {
      if ((row3(mesh.x, i) - p).norm() < (row3(mesh.x, best) - p).norm()) best = i;
    }
    return best;
  };
  for (int f = 0; f < 10; ++f)
    ASSERT_FALSE(cutter.update(a(-0.5 + 0.1 * f), b(-0.5 + 0.1 * f)).blade_unmapped);
  const Real y = 0.5;
  // Away from the blade: the stroke goes on.
  const int far = nearest_node(Vec3(0.05, 0.95, 0.95));
  const Vec3 far_old = invert_at(far);
  EXPECT_FALSE(cutter.update(a(y), b(y)).blade_unmapped);
  mesh.x.row(far) = far_old.transpose();
  // In the blade's path, 0.55 above its tip: the frame is refused, the mesh as it was.
  const int near = nearest_node(Vec3(c, y + 0.1, 0.75));
  const Vec3 near_old = invert_at(near);
  const FrameReport& held = cutter.update(a(y + 0.1), b(y + 0.1));
  EXPECT_TRUE(held.blade_unmapped);
  EXPECT_EQ(held.front_tets, 0);
  EXPECT_EQ(held.committed_new_tets, 0);
  EXPECT_EQ(mesh.num_tets(), cutter.committed_tets());
  // Undone: the same pose has a place in the material again.
  mesh.x.row(near) = near_old.transpose();
  const FrameReport& cut = cutter.update(a(y + 0.1), b(y + 0.1));
  EXPECT_FALSE(cut.blade_unmapped);
  EXPECT_GT(cut.front_tets, 0);
}

// A cut shallower than the tets: the blade's tip runs 0.45 deep (z = 0.55) through a box of
// 0.25 cells. Without keep_partial only the layer the strip crosses completely (z >= 0.75) opens;
// with it, the tets along the tip's path keep their crack too: about 0.45 x 1 on each side, the
// box still one body and valid.
TEST(ProgressiveCutter, AStrokeEndKeepsTheCrackAlongTheTipsPath) {
  const Real c = 0.537;  // the blade's plane x = c, away from the nodes
  const auto cut_area = [&](bool keep_partial, TetMesh& mesh) {
    ProgressiveCutter cutter(mesh);
    Real area = 0;
    const auto add = [&](const FrameReport& report) {
      for (Eigen::Index r = 0; r < report.committed_crack_face_nodes.rows(); ++r) {
        std::array<Vec3, 3> p;
        for (int k = 0; k < 3; ++k) {
          p[static_cast<std::size_t>(k)] = row3(mesh.rest, report.committed_crack_face_nodes(r, k));
          // On the plane, or (a pierce point or a star centre) kept within the front margin.
          EXPECT_LT(std::abs(p[static_cast<std::size_t>(k)].x() - c),
                    4 * kFrontMargin * std::sqrt(3.0) / 4);
        }
        area += 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).norm();
      }
    };
    for (int f = 0; f <= 40; ++f) {
      const Real y = -0.5 + 2.0 * f / 40;
      add(cutter.update(Vec3(c, y, 0.55), Vec3(c, y, 1.5)));
    }
    add(cutter.end_stroke(keep_partial));
    EXPECT_EQ(mesh.num_nodes(), cutter.committed_nodes());
    EXPECT_EQ(mesh.num_tets(), cutter.committed_tets());
    return area;
  };
  TetMesh plain = make_box_mesh({1, 1, 1}, {4, 4, 4});
  TetMesh kept = plain;
  const Real volume = total_volume(plain.rest, plain.tets);
  const Real plain_area = cut_area(false, plain);
  const Real kept_area = cut_area(true, kept);
  expect_valid(plain, volume);
  expect_valid(kept, volume);
  // Both sides of the z >= 0.75 layer, and a few small tets below it the strip crosses whole.
  EXPECT_GE(plain_area, 2 * 0.25 - 1e-9);
  EXPECT_LT(plain_area, 2 * 0.25 + 0.02);
  EXPECT_NEAR(kept_area, 2 * 0.45, 0.05 * 2 * 0.45);
  int count = 0;
  tet_components(kept.tets, &count);
  EXPECT_EQ(count, 1);
}

TEST(ProgressiveCutter, RejectsBadInput) {
  TetMesh mesh = make_box_mesh({1, 1, 1}, {2, 2, 2});
  EXPECT_THROW(ProgressiveCutter(mesh, CutOptions{0.6}), std::invalid_argument);
  ProgressiveCutter cutter(mesh);
  EXPECT_THROW(cutter.update(Vec3::Zero(), Vec3::Zero()), std::invalid_argument);
}

}  // namespace
}  // namespace incise::sim::cut
