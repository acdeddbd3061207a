// Cost of one insertion (split + flip restoration) and one removal (gift-wrapped hole filling)
// in sim/remesh/, on the two-label unit box (4 x 4 x 4 cells) refined at random to about
// 2,000 tets and decimated back. Measures; asserts nothing. Run by hand:
//   bench_remesh [seed]

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include "sim/remesh/flips.h"
#include "sim/remesh/insertion.h"
#include "sim/remesh/vertex_removal.h"
#include "tests/sim/remesh/remesh_fixtures.h"

namespace {

using incise::sim::remesh::InsertStatus;
using incise::sim::remesh::RemeshMesh;
using incise::sim::remesh::RemoveStatus;
using Clock = std::chrono::steady_clock;

void print(const char* what, std::vector<double> us) {
  std::sort(us.begin(), us.end());
  const auto at = [&](double q) { return us[static_cast<size_t>(q * (us.size() - 1))]; };
  std::printf("%-28s n=%5zu  median %7.1f us  p99 %7.1f us  max %7.1f us\n", what, us.size(),
              at(0.5), at(0.99), us.back());
}

}  // namespace

int main(int argc, char** argv) {
  const unsigned seed = argc > 1 ? static_cast<unsigned>(std::atoi(argv[1])) : 1;
  RemeshMesh mesh(incise::sim::remesh::testing::two_label_box());
  incise::sim::remesh::make_constrained_delaunay(mesh);
  std::mt19937 rng(seed);
  std::vector<int> inserted;
  std::vector<double> insert_us[5];
  while (mesh.num_tets() < 2000) {
    const int kind = static_cast<int>(rng() % 5);
    const auto start = Clock::now();
    const auto r = incise::sim::remesh::testing::random_insertion(mesh, kind, rng);
    const double us = std::chrono::duration<double, std::micro>(Clock::now() - start).count();
    if (r.status != InsertStatus::kInserted) continue;
    insert_us[kind].push_back(us);
    inserted.push_back(r.vertex);
  }
  std::printf("refined to %d vertices, %d tets\n", mesh.num_vertices(), mesh.num_tets());
  const char* names[5] = {"insert in tet", "insert on face", "insert on edge",
                          "insert on constrained face", "insert on constrained edge"};
  std::vector<double> all;
  for (int kind = 0; kind < 5; ++kind) {
    print(names[kind], insert_us[kind]);
    all.insert(all.end(), insert_us[kind].begin(), insert_us[kind].end());
  }
  print("insert (all kinds)", all);
  std::shuffle(inserted.begin(), inserted.end(), rng);
  std::vector<double> remove_us;
  int refused = 0;
  while (!inserted.empty()) {
    const int v = inserted.back();
    inserted.pop_back();
    const auto start = Clock::now();
    const auto r = incise::sim::remesh::remove_vertex(mesh, v);
    const double us = std::chrono::duration<double, std::micro>(Clock::now() - start).count();
    if (r.status == RemoveStatus::kRemoved) {
      remove_us.push_back(us);
    } else if (++refused < 1000) {
      inserted.insert(inserted.begin(), v);  // retried later
    }
  }
  print("remove", remove_us);
  std::printf("decimated to %d vertices, %d tets (%d refusals)\n", mesh.num_vertices(),
              mesh.num_tets(), refused);
  return 0;
}
