// Random sequences of insertions (in tets, on faces, on edges, on constrained faces and edges)
// and removals, checking every invariant after every operation, then full decimation, which
// must give back the initial mesh exactly.

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "remesh_fixtures.h"
#include "sim/mesh/tet_adjacency.h"
#include "sim/remesh/flips.h"
#include "sim/remesh/insertion.h"
#include "sim/remesh/remesh_validity.h"
#include "sim/remesh/vertex_removal.h"

namespace incise::sim::remesh {
namespace {

struct Tally {
  int inserted[5] = {0, 0, 0, 0, 0};
  int rejected = 0;
  int removed = 0;
  int not_removed_now = 0;
  FlipCounts flips;
};

// Removes every vertex in `vertices`, retrying those that cannot be removed yet, as the
// decimation list of the seed does; returns those left when a whole pass removes none.
std::vector<int> decimate(RemeshMesh& mesh, std::vector<int> vertices, Real volume) {
  while (!vertices.empty()) {
    std::vector<int> retry;
    for (int v : vertices) {
      if (remove_vertex(mesh, v).status != RemoveStatus::kRemoved) retry.push_back(v);
      EXPECT_EQ(check_remesh_mesh(mesh), "") << "after removing " << v;
      EXPECT_NEAR(remesh_volume(mesh), volume, 1e-12 * volume);
    }
    if (retry.size() == vertices.size()) return retry;
    vertices = retry;
  }
  return {};
}

void run_sequence(const TetMesh& input, unsigned seed, int num_operations, Tally* tally) {
  RemeshMesh mesh(input);
  make_constrained_delaunay(mesh);
  ASSERT_EQ(check_remesh_mesh(mesh), "");
  const auto initial = canonical_tets(mesh);
  const Real volume = remesh_volume(mesh);
  std::mt19937 rng(seed);
  std::vector<int> inserted;
  for (int op = 0; op < num_operations; ++op) {
    // Two insertions for one removal, so that the mesh grows and then shrinks.
    if (inserted.empty() || rng() % 3 != 0) {
      const int kind = static_cast<int>(rng() % 5);
      const InsertResult r = testing::random_insertion(mesh, kind, rng);
      if (r.status == InsertStatus::kInserted) {
        ++tally->inserted[kind];
        inserted.push_back(r.vertex);
        ASSERT_TRUE(r.delaunay_restored) << "after operation " << op;
        for (int f = 0; f < 5; ++f)
          tally->flips.of[f] += r.flips.of[f];
      } else {
        ++tally->rejected;
      }
    } else {
      const size_t i = rng() % inserted.size();
      if (remove_vertex(mesh, inserted[i]).status == RemoveStatus::kRemoved) {
        ++tally->removed;
        inserted.erase(inserted.begin() + static_cast<std::ptrdiff_t>(i));
      } else {
        ++tally->not_removed_now;
      }
    }
    const std::string problem = check_remesh_mesh(mesh);
    ASSERT_EQ(problem, "") << "after operation " << op;
    ASSERT_NEAR(remesh_volume(mesh), volume, 1e-12 * volume) << "after operation " << op;
  }
  const std::vector<int> left = decimate(mesh, inserted, volume);
  EXPECT_TRUE(left.empty()) << left.size() << " inserted vertices could not be removed";
  EXPECT_EQ(mesh.num_vertices(), input.num_nodes());
  EXPECT_TRUE(canonical_tets(mesh) == initial) << "decimation did not restore the mesh";
}

constexpr int kOperations = 1000;

int flips_of(const Tally& tally, FlipKind kind) {
  return tally.flips.of[static_cast<int>(kind)];
}

// Every insertion kind succeeds often, removals succeed, and the restoration exercises the flips
// it needs: 2-3 and 3-2 inside, 2-2 on the boundary.
void expect_coverage(const Tally& tally) {
  for (int kind = 0; kind < 5; ++kind)
    EXPECT_GT(tally.inserted[kind], 50) << "kind " << kind;
  EXPECT_GT(tally.removed, 200);
  EXPECT_GT(flips_of(tally, FlipKind::k23), 100);
  EXPECT_GT(flips_of(tally, FlipKind::k32), 10);
  EXPECT_GT(flips_of(tally, FlipKind::k22), 10);
}

TEST(RemeshSequence, RandomInsertionsAndRemovalsOnABox) {
  Tally tally;
  run_sequence(testing::unit_box(), 11, kOperations, &tally);
  expect_coverage(tally);
  // The lattice has coplanar configurations inside the box.
  EXPECT_GT(flips_of(tally, FlipKind::k44), 0);
}

// Insertions on the interface split the faces of both labels; 4-4 flips re-triangulate it.
TEST(RemeshSequence, RandomInsertionsAndRemovalsOnATwoLabelBox) {
  Tally tally;
  run_sequence(testing::two_label_box(), 23, kOperations, &tally);
  expect_coverage(tally);
  EXPECT_GT(flips_of(tally, FlipKind::k44), 0);
}

TEST(RemeshSequence, RandomInsertionsAndRemovalsOnAJitteredTwoLabelBox) {
  Tally tally;
  run_sequence(testing::jittered_two_label_box(3), 37, kOperations, &tally);
  expect_coverage(tally);
}

// The changes an operation reports describe it exactly: the mesh afterwards is the mesh before,
// minus the removed tets, plus the created ones.
TEST(RemeshSequence, ReportedChangesDescribeTheEdit) {
  RemeshMesh mesh(testing::two_label_box());
  make_constrained_delaunay(mesh);
  std::mt19937 rng(5);
  std::vector<int> inserted;
  const auto tets_by_id = [&] {
    std::set<std::pair<int, std::array<int, 5>>> rows;
    for (int t = 0; t < mesh.num_tet_slots(); ++t) {
      if (!mesh.tet_alive(t)) continue;
      const TetVertices& v = mesh.tet(t);
      rows.insert({t, {v[0], v[1], v[2], v[3], mesh.label(t)}});
    }
    return rows;
  };
  for (int op = 0; op < 200; ++op) {
    const auto before = tets_by_id();
    TetChanges changes;
    if (inserted.empty() || op % 3 == 2) {
      const int v = inserted.empty() ? -1 : inserted[rng() % inserted.size()];
      if (v < 0) continue;
      const RemoveResult r = remove_vertex(mesh, v);
      if (r.status == RemoveStatus::kRemoved) std::erase(inserted, v);
      changes = r.changes;
    } else {
      InsertResult r;
      const int t = [&] {
        for (;;) {
          const int s = static_cast<int>(rng() % mesh.num_tet_slots());
          if (mesh.tet_alive(s)) return s;
        }
      }();
      const int k = static_cast<int>(rng() % 4);
      const TetVertices& v = mesh.tet(t);
      r = insert_on_face(mesh, t, k,
                         point_on_face(mesh, v[kTetFaces[k][0]], v[kTetFaces[k][1]],
                                       v[kTetFaces[k][2]], 0.25, 0.375));
      if (r.status != InsertStatus::kInserted) continue;
      inserted.push_back(r.vertex);
      changes = r.changes;
    }
    auto expected = before;
    for (int t : changes.removed) {
      std::erase_if(expected, [t](const auto& row) { return row.first == t; });
    }
    for (int t : changes.created) {
      const TetVertices& v = mesh.tet(t);
      expected.insert({t, {v[0], v[1], v[2], v[3], mesh.label(t)}});
    }
    ASSERT_EQ(expected, tets_by_id()) << "operation " << op;
  }
}

}  // namespace
}  // namespace incise::sim::remesh
