// Force evaluation cost of the hybrid condensed model against the full model on the same mesh:
// a cube with a 2 x 2 x 2-cell operational block under its top face, corotational (polar)
// everywhere in the full model and in the hybrid's operational region. Prints, per mesh size,
// the node and retained-node counts, the set-up time and the median add_forces time [us].
//   bench_condensed [cells ...]   (default 6 8 10 12)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "tests/sim/models/condensed_fixtures.h"

namespace {

using namespace incise::sim;
using namespace incise::sim::testing;
using Clock = std::chrono::steady_clock;

double median_forces_us(Model& model, const Points& x, const Points& v, int repeats) {
  Points f = Points::Zero(x.rows(), 3);
  std::vector<double> times;
  for (int r = 0; r < repeats; ++r) {
    f.setZero();
    const auto start = Clock::now();
    model.add_forces(x, v, f);
    times.push_back(std::chrono::duration<double, std::micro>(Clock::now() - start).count());
  }
  std::nth_element(times.begin(), times.begin() + repeats / 2, times.end());
  if (!f.allFinite()) std::printf("non-finite forces\n");
  return times[static_cast<std::size_t>(repeats / 2)];
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<int> sizes;
  for (int a = 1; a < argc; ++a)
    sizes.push_back(std::atoi(argv[a]));
  if (sizes.empty()) sizes = {6, 8, 10, 12};
  std::printf("cells nodes tets op_tets retained interior setup_ms full_us hybrid_us\n");
  for (const int cells : sizes) {
    const Real size = 0.04;
    const TetMesh mesh = condensed_box(cells, size);
    const Real cell = size / cells;
    const auto operational = top_block(mesh, cell + 1e-9, 2 * cell);
    const auto materials = condensed_materials();
    const Points x = mesh.rest + random_displacements(mesh.num_nodes(), 1e-4, 1);
    const Points v = random_displacements(mesh.num_nodes(), 1e-2, 2);

    auto full = make_corotational(mesh, materials);
    const auto start = Clock::now();
    HybridCondensedModel hybrid(mesh, operational, materials, make_corotational);
    const double setup_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    const int repeats = 201;
    const double full_us = median_forces_us(*full, x, v, repeats);
    const double hybrid_us = median_forces_us(hybrid, x, v, repeats);
    std::printf("%5d %5d %5d %7d %8zu %8zu %8.1f %7.1f %9.1f\n", cells, mesh.num_nodes(),
                mesh.num_tets(),
                static_cast<int>(std::count(operational.begin(), operational.end(), 1)),
                hybrid.retained_nodes().size(), hybrid.interior_nodes().size(), setup_ms, full_us,
                hybrid_us);
  }
  return 0;
}
