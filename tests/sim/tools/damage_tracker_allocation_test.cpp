// The per-step calls of DamageTracker (record_strain, record_contacts, metrics, metric_rows)
// allocate nothing once the tracker is built: counted through the global operator new of this
// test executable.

#include <atomic>
#include <cstdlib>
#include <new>

#include <gtest/gtest.h>

#include "sim/mesh/box_mesher.h"
#include "sim/tools/damage_tracker.h"

namespace {
std::atomic<long> allocations{0};
}  // namespace

void* operator new(std::size_t size) {
  ++allocations;
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}

namespace incise::sim::tools {
namespace {

TEST(DamageAllocation, StepsAllocateNothing) {
  const TetMesh mesh = make_box_mesh(Vec3(0.04, 0.02, 0.02), Vec3i(4, 2, 2));
  DamageSettings settings;
  settings.strain_thresholds = {{0, 0.05}};
  settings.protected_structures = 2;
  DamageTracker tracker(mesh, settings);
  Points x = mesh.rest;
  x.col(0) *= 1.1;
  const std::array<Real, 2> depths = {0.001, 0};

  const long before = allocations.load();
  Real sum = 0;
  for (int step = 0; step < 50; ++step) {
    tracker.record_strain(step % 2 ? x : mesh.rest, 1e-3);
    tracker.record_contacts(depths, 1e-3);
    sum += metric_rows(tracker.metrics())[0].value;
  }
  EXPECT_EQ(allocations.load() - before, 0);
  EXPECT_GT(sum, 0);
  EXPECT_EQ(tracker.metrics().damaged_elements, mesh.num_tets());
}

}  // namespace
}  // namespace incise::sim::tools
