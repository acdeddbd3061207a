// bench_models (Google Benchmark): the per-tet cost of each model's kernels
// (internal forces, linearisation, one stiffness product) on a ~6k-tet box, and one implicit Euler
// step of the corotational model (QR) on ~6k and ~24k tets at dt = 10 ms, gravity, one face
// clamped, with each linear solver; counters: time per tet, CG iterations per step.
//   bench_models [--benchmark_filter=REGEX]
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>

#include "sim/mesh/box_mesher.h"
#include "sim/scene/scene_run.h"
#include "sim/solve/implicit_euler.h"

namespace incise::bench {
namespace {

using sim::MaterialModel;
using sim::Points;
using sim::Real;
using sim::Vec3;
using sim::Vec3i;

constexpr Real kSize = 0.05;  // a 5 cm cube of soft tissue [m]

// 5 tets per cell (box_mesher.h): 6000 and 24000 tets.
Vec3i cells_for(int thousand_tets) {
  return thousand_tets >= 24 ? Vec3i(16, 15, 20) : Vec3i(10, 10, 12);
}

sim::Scene tissue_scene(MaterialModel model) {
  sim::Scene scene;
  scene.material = {model, 3000, 0.3, 1000, 0.1};
  return scene;
}

// A smooth, moderately large deformation of the rest shape (a stretch, a twist about z and a
// ripple), so that every kernel takes its general path (rotations, nonzero stress).
Points deformed(const Points& rest) {
  Points x(rest.rows(), 3);
  for (Eigen::Index i = 0; i < rest.rows(); ++i) {
    const Vec3 p = rest.row(i).transpose();
    const Real angle = 4 * p.z();  // up to 0.2 rad over the cube
    const Real c = std::cos(angle), s = std::sin(angle);
    const Vec3 q(1.05 * p.x(), 0.97 * p.y(), 0.98 * p.z() + 0.002 * std::sin(60 * p.x()));
    x.row(i) << c * q.x() - s * q.y(), s * q.x() + c * q.y(), q.z();
  }
  return x;
}

enum class Op { forces, prepare_stiffness, stiffness_times };

void BM_Model(benchmark::State& state, MaterialModel model_kind, Op op) {
  const sim::TetMesh mesh = sim::make_box_mesh(Vec3::Constant(kSize), cells_for(6));
  auto model = sim::make_model(tissue_scene(model_kind), mesh);
  const Points x = deformed(mesh.rest);
  const Points v = 0.01 * (x - mesh.rest);
  Points out = Points::Zero(mesh.num_nodes(), 3);
  model->prepare_stiffness(x);
  for (auto _ : state) {
    switch (op) {
      case Op::forces:
        model->add_forces(x, v, out);
        break;
      case Op::prepare_stiffness:
        model->prepare_stiffness(x);
        break;
      case Op::stiffness_times:
        model->add_stiffness_times(v, out);
        break;
    }
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.counters["tets"] = static_cast<double>(mesh.num_tets());
  // Seconds per tet (printed with an SI prefix, e.g. 150n = 150 ns).
  state.counters["per_tet"] = benchmark::Counter(
      static_cast<double>(mesh.num_tets()),
      benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void BM_ImplicitStep(benchmark::State& state, sim::LinearSolver solver,
                     sim::Preconditioner preconditioner) {
  const int thousand_tets = static_cast<int>(state.range(0));
  const sim::TetMesh mesh = sim::make_box_mesh(Vec3::Constant(kSize), cells_for(thousand_tets));
  auto model = sim::make_model(tissue_scene(MaterialModel::corotational), mesh);
  sim::ImplicitEulerSettings settings;
  settings.linear = {solver, preconditioner, sim::CgSettings{1e-6, 2000}};
  sim::ImplicitEuler implicit(settings);
  // Clamped at x = 0, hanging sideways under gravity.
  sim::Prescribed prescribed;
  prescribed.mask = sim::AxisMask::Zero(mesh.num_nodes(), 3);
  prescribed.position = mesh.rest;
  for (Eigen::Index i = 0; i < mesh.num_nodes(); ++i) {
    if (mesh.rest(i, 0) < 1e-9) prescribed.mask.row(i).setOnes();
  }
  const Vec3 gravity(0, 0, -9.81);
  const Points no_loads;
  Points x = mesh.rest;
  Points v = Points::Zero(mesh.num_nodes(), 3);
  const Real dt = 0.01;
  // Two steps first: work arrays, sparsity pattern and warm start are set up once.
  for (int i = 0; i < 2; ++i)
    implicit.step(dt, gravity, no_loads, prescribed, *model, x, v);
  double iterations = 0, converged = 0;
  const int factorisations_before = implicit.system().factorisations();
  for (auto _ : state) {
    const auto report = implicit.step(dt, gravity, no_loads, prescribed, *model, x, v);
    iterations += report.iterations;
    converged += report.converged ? 1 : 0;
    benchmark::DoNotOptimize(x.data());
  }
  state.counters["tets"] = static_cast<double>(mesh.num_tets());
  state.counters["cg_iters"] = benchmark::Counter(iterations, benchmark::Counter::kAvgIterations);
  state.counters["converged"] = benchmark::Counter(converged, benchmark::Counter::kAvgIterations);
  if (preconditioner == sim::Preconditioner::incomplete_cholesky) {
    state.counters["factorisations"] =
        benchmark::Counter(implicit.system().factorisations() - factorisations_before,
                           benchmark::Counter::kAvgIterations);
  }
}

#define INCISE_MODEL_BENCHMARKS(kind)                                                           \
  BENCHMARK_CAPTURE(BM_Model, kind##_forces, MaterialModel::kind, Op::forces)                   \
      ->Unit(benchmark::kMicrosecond)                                                           \
      ->MinTime(0.1);                                                                           \
  BENCHMARK_CAPTURE(BM_Model, kind##_prepare_stiffness, MaterialModel::kind,                    \
                    Op::prepare_stiffness)                                                      \
      ->Unit(benchmark::kMicrosecond)                                                           \
      ->MinTime(0.1);                                                                           \
  BENCHMARK_CAPTURE(BM_Model, kind##_stiffness_times, MaterialModel::kind, Op::stiffness_times) \
      ->Unit(benchmark::kMicrosecond)                                                           \
      ->MinTime(0.1)

INCISE_MODEL_BENCHMARKS(mass_spring);
INCISE_MODEL_BENCHMARKS(linear);
INCISE_MODEL_BENCHMARKS(corotational);
INCISE_MODEL_BENCHMARKS(corotational_polar);
INCISE_MODEL_BENCHMARKS(stvk);
INCISE_MODEL_BENCHMARKS(neohookean);

#define INCISE_IMPLICIT_BENCHMARK(solver, preconditioner, repeats)                         \
  BENCHMARK_CAPTURE(BM_ImplicitStep, solver##_##preconditioner, sim::LinearSolver::solver, \
                    sim::Preconditioner::preconditioner)                                   \
      ->Arg(6)                                                                             \
      ->Arg(24)                                                                            \
      ->Unit(benchmark::kMillisecond)                                                      \
      ->Iterations(repeats)

INCISE_IMPLICIT_BENCHMARK(matrix_free_cg, jacobi, 10);
INCISE_IMPLICIT_BENCHMARK(matrix_free_cg, block_jacobi, 10);
INCISE_IMPLICIT_BENCHMARK(assembled_cg, jacobi, 10);
INCISE_IMPLICIT_BENCHMARK(assembled_cg, block_jacobi, 10);
INCISE_IMPLICIT_BENCHMARK(assembled_cg, incomplete_cholesky, 20);
INCISE_IMPLICIT_BENCHMARK(assembled_ldlt, none, 4);

}  // namespace
}  // namespace incise::bench

BENCHMARK_MAIN();
