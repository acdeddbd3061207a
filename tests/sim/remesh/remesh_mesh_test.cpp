#include "sim/remesh/remesh_mesh.h"

#include <algorithm>
#include <set>
#include <stdexcept>

#include <gtest/gtest.h>

#include "remesh_fixtures.h"
#include "sim/mesh/boundary_surface.h"
#include "sim/mesh/tet_adjacency.h"
#include "sim/remesh/flips.h"
#include "sim/remesh/insertion.h"
#include "sim/remesh/remesh_validity.h"
#include "sim/remesh/vertex_removal.h"

namespace incise::sim::remesh {
namespace {

std::set<std::array<int, 5>> tet_set(const TetMesh& mesh) {
  std::set<std::array<int, 5>> rows;
  for (int t = 0; t < mesh.num_tets(); ++t) {
    std::array<int, 4> v = {mesh.tets(t, 0), mesh.tets(t, 1), mesh.tets(t, 2), mesh.tets(t, 3)};
    std::sort(v.begin(), v.end());
    rows.insert({v[0], v[1], v[2], v[3], mesh.labels(t)});
  }
  return rows;
}

TEST(RemeshMesh, RoundTripsATetMesh) {
  const TetMesh box = testing::two_label_box();
  const RemeshMesh mesh(box);
  EXPECT_EQ(mesh.num_vertices(), box.num_nodes());
  EXPECT_EQ(mesh.num_tets(), box.num_tets());
  const TetMesh back = mesh.to_tet_mesh();
  EXPECT_EQ(back.rest, box.rest);
  EXPECT_EQ(tet_set(back), tet_set(box));
}

// Constrained faces: the 6 x 16 x 2 boundary triangles of the box, plus 16 x 2 on the plane
// x = 0.5 between the labels.
TEST(RemeshMesh, ConstrainsTheBoundaryAndTheLabelInterface) {
  const RemeshMesh one(testing::unit_box());
  EXPECT_EQ(one.original_constrained_faces().size(), 192u);
  const RemeshMesh two(testing::two_label_box());
  ASSERT_EQ(two.original_constrained_faces().size(), 192u + 32u);
  int on_interface = 0;
  for (const auto& face : two.original_constrained_faces()) {
    on_interface += two.point(face[0]).x() == 0.5 && two.point(face[1]).x() == 0.5 &&
                    two.point(face[2]).x() == 0.5;
  }
  EXPECT_EQ(on_interface, 32);
  // Facets: the six box sides; with two labels the four sides the interface crosses split in
  // two, plus the interface itself.
  EXPECT_EQ(one.num_facets(), 6);
  EXPECT_EQ(two.num_facets(), 2 + 4 * 2 + 1);
}

TEST(RemeshMesh, RejectsAnInvertedTet) {
  TetMesh box = testing::unit_box();
  std::swap(box.tets(3, 0), box.tets(3, 1));
  EXPECT_THROW(RemeshMesh{box}, std::invalid_argument);
}

// The box mesh has eight cospherical corners per cell; flipping it towards its constrained
// Delaunay tetrahedralisation gets stuck on some faces, which are frozen as constraints. The
// result passes every check, keeps the volume, and is a fixed point.
TEST(RemeshMesh, FlipsTheBoxToItsConstrainedDelaunayState) {
  for (const TetMesh& box : {testing::unit_box(), testing::two_label_box()}) {
    RemeshMesh mesh(box);
    const size_t constrained = mesh.original_constrained_faces().size();
    const int frozen = make_constrained_delaunay(mesh);
    EXPECT_EQ(mesh.original_constrained_faces().size(), constrained + frozen);
    EXPECT_LT(frozen, mesh.num_tets() / 4);  // most interior faces flip to Delaunay
    EXPECT_EQ(check_remesh_mesh(mesh), "");
    EXPECT_NEAR(remesh_volume(mesh), 1.0, 1e-14);
    // A second pass finds nothing to do: the state is a fixed point.
    const auto state = canonical_tets(mesh);
    EXPECT_EQ(make_constrained_delaunay(mesh), 0);
    EXPECT_EQ(canonical_tets(mesh), state);
  }
}

// Two flat tets on either side of a triangle are not Delaunay: one 2-3 flip replaces the shared
// face by the edge between the apexes, keeping the volume; the three new tets share that edge.
TEST(RemeshFlips, TwoThreeFlipOfAFlatPair) {
  Points rest(5, 3);
  rest << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0.3, 0.3, 0.2, 0.3, 0.3, -0.2;
  Tets tets(2, 4);
  tets << 0, 1, 2, 3, 0, 2, 1, 4;
  RemeshMesh mesh(make_tet_mesh(rest, tets));
  const Real volume = remesh_volume(mesh);
  ASSERT_FALSE(is_locally_delaunay(mesh, 0, 3));
  std::vector<int> created;
  ASSERT_EQ(flip_face(mesh, 0, 3, &created), FlipKind::k23);
  EXPECT_EQ(created.size(), 3u);
  EXPECT_EQ(mesh.num_tets(), 3);
  for (int t : created) {
    EXPECT_GE(mesh.local_index(t, 3), 0);
    EXPECT_GE(mesh.local_index(t, 4), 0);
  }
  EXPECT_NEAR(remesh_volume(mesh), volume, 1e-16);
  EXPECT_EQ(check_remesh_mesh(mesh), "");
  // Every outer face is constrained (boundary), so nothing more can flip.
  EXPECT_EQ(restore_delaunay(mesh, created), 0);
}

// The checker is not vacuous: the box as meshed (five tets per cell) is not Delaunay, and a
// mesh with a tet taken away has uncovered faces.
TEST(RemeshValidity, FlagsANonDelaunayMeshAndAHole) {
  const RemeshMesh raw(testing::unit_box());
  EXPECT_NE(check_remesh_mesh(raw), "");
  RemeshMesh holed(testing::unit_box());
  make_constrained_delaunay(holed);
  std::vector<int> interior;
  for (int t = 0; t < holed.num_tet_slots() && interior.empty(); ++t) {
    bool inside = true;
    for (int k = 0; k < 4; ++k)
      inside = inside && holed.neighbor(t, k) >= 0;
    if (inside) interior.push_back(t);
  }
  ASSERT_EQ(interior.size(), 1u);
  const TetVertices v = holed.tet(interior[0]);
  // Re-creating the tet with two vertices swapped (inverted) is caught.
  holed.replace_tets(interior, std::vector<NewTet>{{{v[1], v[0], v[2], v[3]}, 0}}, {}, nullptr);
  EXPECT_NE(check_remesh_mesh(holed).find("not positively oriented"), std::string::npos);
}

// Refused insertions leave the mesh as it was: a point outside the named tet, a point off the
// boundary face or edge it is said to split (the surface must not move).
TEST(RemeshInsertion, RefusesPointsOffTheirSimplex) {
  RemeshMesh mesh(testing::two_label_box());
  make_constrained_delaunay(mesh);
  const auto before = canonical_tets(mesh);
  EXPECT_EQ(insert_in_tet(mesh, 0, Vec3(2, 2, 2)).status, InsertStatus::kNotInside);
  int t = 0, k = 0;  // a boundary face
  for (t = 0; t < mesh.num_tet_slots(); ++t) {
    for (k = 0; k < 4 && mesh.neighbor(t, k) >= 0; ++k) {
    }
    if (k < 4) break;
  }
  const TetVertices w = mesh.tet(t);
  const int a = w[kTetFaces[k][0]], b = w[kTetFaces[k][1]], c = w[kTetFaces[k][2]];
  const Vec3 on = point_on_face(mesh, a, b, c, 0.25, 0.25);
  const Vec3 normal = (mesh.point(b) - mesh.point(a)).cross(mesh.point(c) - mesh.point(a));
  EXPECT_EQ(insert_on_face(mesh, t, k, on + 1e-9 * normal).status, InsertStatus::kOffConstraint);
  EXPECT_EQ(insert_on_edge(mesh, a, b, point_on_edge(mesh, a, b, 0.5) + 1e-9 * normal).status,
            InsertStatus::kOffConstraint);
  EXPECT_EQ(mesh.num_vertices(), 125);
  EXPECT_TRUE(canonical_tets(mesh) == before);
  // The same points exactly on the face and edge are accepted.
  EXPECT_EQ(insert_on_face(mesh, t, k, on).status, InsertStatus::kInserted);
  EXPECT_EQ(check_remesh_mesh(mesh), "");
}

// A face frozen as a lone constraint inside a label region: a point may split it, but not its
// free edges. A constrained Delaunay mesh need not exist with the new point (3D), and the
// insertion says so exactly when a face is left not locally Delaunay; removing the point
// restores the mesh.
TEST(RemeshMesh, FrozenFaceCanBeSplitButNotItsFreeEdges) {
  RemeshMesh mesh(testing::unit_box());
  make_constrained_delaunay(mesh);
  int t = 0, k = 0;
  for (t = 0; t < mesh.num_tet_slots(); ++t) {
    for (k = 0; k < 4; ++k) {
      if (mesh.neighbor(t, k) >= 0 && mesh.face_parent(t, k) < 0) break;
    }
    if (k < 4) break;
  }
  const int facet = mesh.constrain_face(t, k);
  EXPECT_EQ(facet, mesh.num_facets() - 1);
  ASSERT_EQ(check_remesh_mesh(mesh), "");
  const auto before = canonical_tets(mesh);
  const TetVertices v = mesh.tet(t);
  const int a = v[kTetFaces[k][0]], b = v[kTetFaces[k][1]], c = v[kTetFaces[k][2]];
  EXPECT_EQ(insert_on_edge(mesh, a, b, point_on_edge(mesh, a, b, 0.5)).status,
            InsertStatus::kOnFreeConstraintEdge);
  const InsertResult r = insert_on_face(mesh, t, k, point_on_face(mesh, a, b, c, 0.25, 0.25));
  ASSERT_EQ(r.status, InsertStatus::kInserted);
  const std::string problem = check_remesh_mesh(mesh);
  EXPECT_EQ(r.delaunay_restored, problem.empty()) << problem;
  EXPECT_EQ(remove_vertex(mesh, r.vertex).status, RemoveStatus::kRemoved);
  EXPECT_EQ(check_remesh_mesh(mesh), "");
  EXPECT_TRUE(canonical_tets(mesh) == before);
  EXPECT_EQ(remove_vertex(mesh, a).status, RemoveStatus::kOriginalVertex);
}

}  // namespace
}  // namespace incise::sim::remesh
