// A surgical scene's steps allocate nothing: with no tool near the tissue, with a probe held
// pressed in, with a grasper holding a lifted patch, and a scalpel's stroke between its cut frames.
// Counted through the C allocator of this test executable (its own, so that no other test's
// allocations count). Frames that change the mesh (refinement, coarsening, cut frames)
// still allocate: they grow arrays.
// To find an allocation: TRAP_ALLOC=1 gdb -ex run -ex bt --args
//   build/bin/sim_surgery_allocation_tests --gtest_filter=...  (it traps on the first one counted)

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <numbers>
#include <span>
#include <vector>

#include <gtest/gtest.h>

#include "sim/surgery/scene_presets.h"
#include "sim/surgery/surgical_scene.h"

namespace {
std::atomic<long> allocations{0};
std::atomic<bool> counting{false};  // inside allocations_over or a counted step

void count() {
  ++allocations;
  if (counting.load() && std::getenv("TRAP_ALLOC") != nullptr) __builtin_trap();
}
}  // namespace

// The C allocator itself, interposed (glibc), so that Eigen's matrices, which take their memory
// from std::malloc and not from operator new, count as well as std containers and strings (the
// default operator new calls malloc).
extern "C" {
void* __libc_malloc(std::size_t size);
void* __libc_calloc(std::size_t count, std::size_t size);
void* __libc_realloc(void* p, std::size_t size);
void* malloc(std::size_t size) {
  count();
  return __libc_malloc(size);
}
void* calloc(std::size_t n, std::size_t size) {
  count();
  return __libc_calloc(n, size);
}
void* realloc(void* p, std::size_t size) {
  count();
  return __libc_realloc(p, size);
}
}

namespace incise::sim::surgery {
namespace {

const Vec3 kSize(0.06, 0.06, 0.03);

// A corotational block held on its base (make_block_surgery, the palpation block's builder), with
// the liver station's ambient damping and the given tools.
SurgicalSceneSpec block(std::vector<ToolSpec> tools) {
  Scene scene;
  scene.mesh.box = {kSize, Vec3i(6, 6, 3)};
  scene.material = {MaterialModel::corotational_polar, 5000, 0.45, 1000, 0.3};
  scene.constraints = {
      {{Box3(Vec3::Zero(), Vec3(kSize.x(), kSize.y(), 0))}, {true, true, true}, Vec3::Zero()}};
  scene.solver.dt = 1e-4;
  scene.solver.steps = 1;
  SurgicalSceneSpec spec = make_block_surgery(scene).spec;
  spec.tools = std::move(tools);
  spec.ambient_damping = 20;
  return spec;
}

ToolInput at(const Vec3& tip, Real jaw = 1) {
  ToolInput in;
  in.tip = tip;
  in.orientation = Eigen::Quaternion<Real>(Eigen::AngleAxis<Real>(std::numbers::pi, Vec3::UnitX()));
  in.jaw = jaw;
  return in;
}

// Allocations over `steps` steps at the input.
long allocations_over(SurgicalScene& scene, const ToolInput& input, int steps) {
  const long before = allocations.load();
  counting = true;
  for (int n = 0; n < steps; ++n)
    scene.step(std::span(&input, 1));
  counting = false;
  return allocations.load() - before;
}

TEST(SurgicalSceneAllocation, IdleStepsAllocateNothing) {
  SurgicalScene scene(block({make_tool(ToolKind::probe)}));
  const ToolInput above = at(Vec3(0.03, 0.03, kSize.z() + 0.02));
  allocations_over(scene, above, 10);  // the first steps make the tool
  EXPECT_EQ(allocations_over(scene, above, 200), 0);
  EXPECT_TRUE(scene.state_finite());
}

TEST(SurgicalSceneAllocation, AHeldProbeAllocatesNothing) {
  SurgicalScene scene(block({make_tool(ToolKind::probe)}));
  const Real radius = tools::ProbeSettings{}.radius;
  const Vec3 top(0.031, 0.029, kSize.z() + radius);
  for (int n = 0; n < 1000; ++n) {
    const ToolInput in = at(top - Vec3(0, 0, 0.004 * n / 1000.0));
    scene.step(std::span(&in, 1));
  }
  const ToolInput pressed = at(top - Vec3(0, 0, 0.004));
  allocations_over(scene, pressed, 100);
  EXPECT_EQ(allocations_over(scene, pressed, 200), 0);
  EXPECT_TRUE(scene.tool_view(0).touching);
}

TEST(SurgicalSceneAllocation, AGrasperHoldingAllocatesNothing) {
  SurgicalScene scene(block({make_tool(ToolKind::grasper)}));
  const Vec3 surface(0.03, 0.03, kSize.z() + 0.0005);
  for (int n = 0; n <= 300; ++n) {
    const ToolInput in = at(surface, 1 - n / 300.0);  // close on the surface
    scene.step(std::span(&in, 1));
  }
  for (int n = 0; n <= 500; ++n) {
    const ToolInput in = at(surface + Vec3(0, 0, 0.005 * n / 500.0), 0);  // lift 5 mm
    scene.step(std::span(&in, 1));
  }
  ASSERT_TRUE(scene.tool_view(0).touching) << "the grasper should hold";
  const ToolInput lifted = at(surface + Vec3(0, 0, 0.005), 0);
  EXPECT_EQ(allocations_over(scene, lifted, 200), 0);
}

// A scalpel's stroke: the steps between cut frames (every cut_every steps the cutter changes the
// mesh, which grows arrays) allocate nothing.
TEST(SurgicalSceneAllocation, AScalpelBetweenCutFramesAllocatesNothing) {
  SurgicalSceneSpec spec = block({make_tool(ToolKind::scalpel)});
  const int every = spec.cut_every;
  SurgicalScene scene(std::move(spec));
  const Vec3 start(0.015, 0.031, kSize.z() + 0.005);
  const Vec3 depth(0, 0, -0.011);
  const auto input = [&](int n) {  // in over 500 steps, then along x at 5 cm/s
    const Real in = std::min(1.0, n / 500.0);
    return at(start + in * depth + Vec3(0.05 * 1e-4 * std::max(0, n - 500), 0, 0));
  };
  int n = 0;
  for (; n < 700; ++n) {
    const ToolInput in = input(n);
    scene.step(std::span(&in, 1));
  }
  ASSERT_GT(scene.tool_view(0).blade_depth, 0) << "the blade should be in the tissue";
  long between = 0;
  for (; n < 3500; ++n) {
    const ToolInput in = input(n);
    const bool cut_frame = scene.steps() % every == 0;  // step() cuts first on these
    const long before = allocations.load();
    counting = !cut_frame;
    scene.step(std::span(&in, 1));
    counting = false;
    if (!cut_frame) between += allocations.load() - before;
  }
  EXPECT_EQ(between, 0);
  EXPECT_GT(scene.damage().cut_area, 0);
}

}  // namespace
}  // namespace incise::sim::surgery
