// bench_kernels: how far each model's per-tet work is from this machine's limit, on one core.
//
// First it measures the machine: the peak rate of independent double-precision multiplies and adds
// in SIMD registers (the AVX2 clone where the processor has it), and the memory bandwidth of a
// triad over arrays far larger than the caches. Then, for each model on a box of about 3k and 24k
// tets in a rotating, deformed state (each step turns it by a milliradian, so that warm starts
// see what a simulation step gives them), the median time per tet of add_forces and of
// add_stiffness_times, and beside it the kernel's limit: its bytes per tet (element data, plus its
// share of the node arrays x, v and f) over the bandwidth, or its flops per tet over the peak,
// whichever is longer. The flops are counted by hand from the vectorised kernels' code
// (corotational_batch.cpp: a square root or a division counts one, comparisons none); the scalar
// kernels are not counted ("-"). The corotational models also run their scalar reference
// (add_forces_scalar) for the speed-up.
//   bench_kernels [--quick] [--model NAME]   (--quick: the 3k box only, fewer repeats; --model:
//   the models whose name starts with NAME)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "bench/median.h"
#include "sim/mesh/box_mesher.h"
#include "sim/models/corotational_fem.h"
#include "sim/scene/scene_run.h"

#pragma GCC diagnostic ignored "-Wpsabi"

namespace {

using namespace incise::sim;
using Clock = std::chrono::steady_clock;
using Lanes = double __attribute__((vector_size(32)));

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

using incise::bench::median;

// Twelve independent chains of x <- x * a + b (a multiply and an add each; contracted into one
// fused multiply-add where the processor has it, as in the kernels): flops per second.
[[gnu::target_clones("arch=x86-64-v3", "default")]] double peak_flops(long rounds) {
  Lanes x[12];
  for (int k = 0; k < 12; ++k)
    x[k] = Lanes{1.0 + k, 1.1 + k, 1.2 + k, 1.3 + k};
  const Lanes a = {0.999999, 0.999999, 0.999999, 0.999999};
  const Lanes b = {1e-6, 1e-6, 1e-6, 1e-6};
  const Clock::time_point start = Clock::now();
  for (long r = 0; r < rounds; ++r) {
    for (int k = 0; k < 12; ++k)
      x[k] = x[k] * a + b;
  }
  const double elapsed = seconds_since(start);
  double sink = 0;
  for (int k = 0; k < 12; ++k)
    sink += x[k][0];
  if (sink == 42) std::puts("");  // keeps the chains alive
  return 12.0 * 4 * 2 * static_cast<double>(rounds) / elapsed;
}

// Triad a = b + s c over three 64 MiB arrays: bytes per second, counting the read of b and c and
// the write of a (and the read of a a write-allocate cache makes).
double bandwidth() {
  const std::size_t n = std::size_t(8) << 20;
  std::vector<double> a(n, 0), b(n, 1), c(n, 2);
  std::vector<double> rates;
  for (int repeat = 0; repeat < 5; ++repeat) {
    const Clock::time_point start = Clock::now();
    for (std::size_t i = 0; i < n; ++i)
      a[i] = b[i] + 0.5 * c[i];
    rates.push_back(4.0 * sizeof(double) * static_cast<double>(n) / seconds_since(start));
    std::swap(a, b);
  }
  if (a[n / 2] == 42) std::puts("");
  return median(rates);
}

struct Machine {
  double flops = 0;  // per second
  double bytes = 0;  // per second
};

struct KernelCost {
  double flops = -1;  // per tet; < 0: not counted
  double bytes = 0;   // per tet
};

// The limit [ns per tet] of a kernel on machine m.
double limit_ns(const KernelCost& cost, const Machine& m) {
  const double memory = cost.bytes / m.bytes;
  const double compute = cost.flops > 0 ? cost.flops / m.flops : 0;
  return 1e9 * std::max(memory, compute);
}

// A box of soft tissue [m] turned about a skew axis by `angle` and deformed smoothly (a stretch,
// a twist and a ripple), so that every kernel takes its general path.
Points state_at(const Points& rest, double angle) {
  const Mat3 turn = Eigen::AngleAxis<Real>(angle, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  Points x(rest.rows(), 3);
  for (Eigen::Index i = 0; i < rest.rows(); ++i) {
    const Vec3 p = rest.row(i).transpose();
    const Real twist = 4 * p.z();
    const Real c = std::cos(twist), s = std::sin(twist);
    const Vec3 q(1.05 * p.x(), 0.97 * p.y(), 0.98 * p.z() + 0.002 * std::sin(60 * p.x()));
    x.row(i) = (turn * Vec3(c * q.x() - s * q.y(), s * q.x() + c * q.y(), q.z())).transpose();
  }
  return x;
}

struct Timing {
  double forces_ns = 0;     // per tet per call, median
  double stiffness_ns = 0;  // per tet per add_stiffness_times
  double iterations = 0;    // Newton iterations per tet (polar batch)
};

// Median over `repeats` of the time per tet of `calls` calls of work(step).
double time_per_tet(int tets, int repeats, int calls, const std::function<void(int)>& work) {
  std::vector<double> ns;
  for (int r = 0; r < repeats; ++r) {
    const Clock::time_point start = Clock::now();
    for (int c = 0; c < calls; ++c)
      work(r * calls + c);
    ns.push_back(1e9 * seconds_since(start) / (static_cast<double>(calls) * tets));
  }
  return median(ns);
}

struct Box {
  TetMesh mesh;
  std::vector<Points> states;  // 16 states a milliradian apart, cycled through
  Points v;
};

Box make_box(const Vec3i& cells) {
  Box box{make_box_mesh(Vec3::Constant(0.05), cells), {}, {}};
  for (int s = 0; s < 16; ++s)
    box.states.push_back(state_at(box.mesh.rest, 0.3 + 1e-3 * s));
  box.v = 0.01 * (box.states[1] - box.states[0]) / 1e-3;
  return box;
}

Timing time_model(Model& model, const Box& box, int repeats, bool scalar_reference) {
  const int tets = box.mesh.num_tets();
  Points f = Points::Zero(box.mesh.num_nodes(), 3);
  auto* corotational = dynamic_cast<CorotationalFem*>(&model);
  const int calls = std::max(4, 2'000'000 / tets / (scalar_reference ? 4 : 1));
  auto forces = [&](int step) {
    const Points& x = box.states[static_cast<std::size_t>(step % 16)];
    if (scalar_reference) {
      corotational->add_forces_scalar(x, box.v, f);
    } else {
      model.add_forces(x, box.v, f);
    }
  };
  for (int s = 0; s < 16; ++s)
    forces(s);  // warm starts and caches
  Timing t;
  t.forces_ns = time_per_tet(tets, repeats, calls, forces);
  if (corotational != nullptr && !scalar_reference)
    t.iterations = corotational->batch().last_newton_iterations();
  model.prepare_stiffness(box.states[0]);
  t.stiffness_ns = time_per_tet(tets, repeats, calls, [&](int step) {
    model.add_stiffness_times(box.states[static_cast<std::size_t>(step % 16)], f);
  });
  return t;
}

// Bytes per tet: element data plus the node arrays' share (x and v read, f read and written).
double bytes_per_tet(double element_bytes, const Box& box) {
  return element_bytes + 4.0 * 3 * sizeof(Real) * box.mesh.num_nodes() / box.mesh.num_tets();
}

// The vectorised kernels' flops per tet (corotational_batch.cpp, counted line by line): F and
// det F 68, the stress of the stretch 75 (+45 for U = R^T F), the damping 209, the nodal forces
// 72; polar adds 67 per call and 202 per Newton iteration, QR 48 for Gram-Schmidt and 64 for
// its dR/dF term.
double batch_flops(RotationExtraction extraction, double iterations) {
  const double common = 68 + 75 + 45 + 209 + 72;
  return extraction == RotationExtraction::polar ? common + 67 + 202 * iterations
                                                 : common + 48 + 64;
}

struct Row {
  std::string name;
  MaterialModel kind;
};

}  // namespace

int main(int argc, char** argv) {
  // --quick: the 3k box only, fewer repeats; --model NAME: that model only (for profiling).
  bool quick = false;
  std::string only;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--quick") == 0) {
      quick = true;
    } else if (std::strcmp(argv[i], "--model") == 0 && i + 1 < argc) {
      only = argv[++i];
    } else {
      std::fprintf(stderr, "usage: bench_kernels [--quick] [--model NAME]\n");
      return 2;
    }
  }
  Machine machine;
  machine.flops = peak_flops(quick ? 20'000'000 : 100'000'000);
  machine.bytes = bandwidth();
  std::printf(
      "machine: peak %.1f Gflop/s (SIMD multiply and add, one core), memory %.1f GB/s "
      "(triad)\n",
      machine.flops * 1e-9, machine.bytes * 1e-9);

  const std::vector<Row> rows = {
      {"corotational_polar", MaterialModel::corotational_polar},
      {"corotational (QR)", MaterialModel::corotational},
      {"stvk", MaterialModel::stvk},
      {"neohookean", MaterialModel::neohookean},
      {"linear", MaterialModel::linear},
      {"mss", MaterialModel::mass_spring},
  };
  std::vector<Vec3i> sizes = {Vec3i(9, 8, 8)};
  if (!quick) sizes.push_back(Vec3i(16, 15, 20));
  const int repeats = quick ? 3 : 7;
  for (const Vec3i& cells : sizes) {
    const Box box = make_box(cells);
    std::printf("\n%d tets, %d nodes\n", box.mesh.num_tets(), box.mesh.num_nodes());
    std::printf("  %-24s %10s %10s %10s %9s %9s %10s %12s\n", "model, kernel", "ns/tet", "limit ns",
                "of limit", "flops", "bytes", "Newton", "stiffness ns");
    for (const Row& row : rows) {
      if (!only.empty() && row.name.rfind(only, 0) != 0) continue;
      Scene scene;
      scene.material = {row.kind, 3000, 0.45, 1000, 0.1};
      auto model = make_model(scene, box.mesh);
      const bool batched =
          row.kind == MaterialModel::corotational_polar || row.kind == MaterialModel::corotational;
      const Timing t = time_model(*model, box, repeats, false);
      KernelCost cost;
      if (batched) {
        const auto extraction = row.kind == MaterialModel::corotational_polar
                                    ? RotationExtraction::polar
                                    : RotationExtraction::qr;
        cost.flops = batch_flops(extraction, t.iterations);
        cost.bytes = bytes_per_tet(120 + (extraction == RotationExtraction::polar ? 64 : 0), box);
      } else {
        // TetFemModel: tets, Dm^-1, Lame, damping, volume, alive; mss: springs of ~6 per tet.
        cost.bytes = bytes_per_tet(row.kind == MaterialModel::mass_spring ? 6 * 40 : 121, box);
      }
      const double limit = limit_ns(cost, machine);
      char flops[32] = "-";
      if (cost.flops > 0) std::snprintf(flops, sizeof flops, "%.0f", cost.flops);
      char newton[32] = "";
      if (row.kind == MaterialModel::corotational_polar)
        std::snprintf(newton, sizeof newton, "%.2f", t.iterations);
      std::printf(
          "  %-24s %10.1f %10.1f %9.1fx %9s %9.0f %10s %12.1f\n",
          (row.name + (batched || row.kind == MaterialModel::mass_spring ? ", SIMD" : ", scalar"))
              .c_str(),
          t.forces_ns, limit, t.forces_ns / limit, flops, cost.bytes, newton, t.stiffness_ns);
      if (batched) {
        const Timing reference = time_model(*model, box, repeats, true);
        std::printf("  %-24s %10.1f %10s %9s %9s %9s %10s %12s   (SIMD %.1fx faster)\n",
                    (row.name + ", scalar").c_str(), reference.forces_ns, "", "", "", "", "", "",
                    reference.forces_ns / t.forces_ns);
      }
    }
  }
  return 0;
}
