// Paloc 2006's probing experiment (its Figure 6): a mass-spring tissue block, clamped at its base,
// probed by a sphere tool that pushes into the top surface and slides along it, simulated on
//   low       a coarse box mesh,
//   high      a fine box mesh (the reference),
//   adaptive  the coarse mesh refined near the tool (to the fine mesh's size, l_min = the fine
//             mesh's smallest altitude) and decimated behind it, every kAdaptEvery steps.
// Each runs symplectic Euler at its own stable step (CFL on the shortest rest edge, see
// min_rest_edge; for the adaptive mesh the smallest over the run). Measured: time per step
// (adaptation included), tets, dt, and the error of low and adaptive against high in the probed
// region: the displacement of the top-surface nodes within 2 tool radii of the tool path, against
// the high-resolution displacement field sampled at their rest positions (barycentric in the fine
// tet holding them), relative to the largest high-resolution displacement there. Prints a table and
// writes a CSV. Run (from the repository root, about 20 s with -O3):
//   bench_probing [results/probing.csv]

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "sim/mesh/box_mesher.h"
#include "sim/remesh/adaptive_body.h"
#include "sim/remesh/state_transfer.h"
#include "sim/scene/scene_run.h"
#include "sim/solve/stable_time_step.h"
#include "svg_plot.h"

using namespace incise::sim;
using namespace incise::sim::remesh;
using Clock = std::chrono::steady_clock;

namespace {

// The block and its tissue (soft, MSS as in the seed).
const Vec3 kSize(0.10, 0.10, 0.04);
constexpr Real kYoungs = 3000;
constexpr Real kPoisson = 0.3;  // only for the wave speed of the CFL step: MSS has no free nu
constexpr Real kDensity = 1000;
// No gravity: a sag of the whole block (rho g H^2 / E ~ 5 mm here) would ring for the whole run
// and depends on the resolution of the whole mesh, which local refinement does not change; the
// experiment is about the response to the tool.
const Vec3 kGravity(0, 0, 0);

// The tool: radius, path (touch at x0, push kDepth down, slide to x1, hold), penalty.
constexpr Real kRadius = 0.008;
constexpr Real kDepth = 0.006;
constexpr Real kX0 = 0.03, kX1 = 0.07, kY = 0.05;
constexpr Real kPushEnd = 0.15, kSlideEnd = 0.40, kEnd = 0.45;  // [s]
// Penalty per node in contact, kPenalty m_i / dt^2 per metre of depth: a fixed fraction of the
// depth is removed per step whatever the node's mass, so that the contact is about the same
// geometric constraint on every mesh (a per-node stiffness would load a fine mesh harder).
constexpr Real kPenalty = 0.2;
constexpr int kAdaptEvery = 10;
// The error is measured every kSampleEvery (the timeline plotted), and tabled at the end of the
// push, the middle of the slide and the end (samples kTabled).
constexpr Real kSampleEvery = 0.025;
constexpr std::size_t kSamples = 18;  // kEnd / kSampleEvery
const std::array<std::size_t, 3> kTabled{5, 10, 17};
Real sample_time(std::size_t s) {
  return kSampleEvery * static_cast<Real>(s + 1);
}

Vec3 tool_centre(Real t) {
  const Real top = kSize.z() + kRadius;
  if (t <= kPushEnd) return Vec3(kX0, kY, top - kDepth * t / kPushEnd);
  const Real s = std::min(1.0, (t - kPushEnd) / (kSlideEnd - kPushEnd));
  return Vec3(kX0 + s * (kX1 - kX0), kY, top - kDepth);
}

ModelFactory mss() {
  Scene scene;
  scene.material.model = MaterialModel::mass_spring;
  scene.material.youngs_modulus = kYoungs;
  scene.material.poisson_ratio = kPoisson;
  scene.material.density = kDensity;
  scene.material.damping = 0.3;
  return [scene](const TetMesh& mesh) { return make_model(scene, mesh); };
}

// The mass-spring system's stability length is its shortest spring (rest edge): a spring of
// length l between the nodes of its tets has k = E V / l^2 against masses ~ density V, so
// omega ~ c / l. A sliver (small altitude, long edges) has small V, hence a softer spring, and does
// not lower the limit as it does for FEM (whose CFL uses the altitude). Refinement and decimation
// both keep every new edge >= l_min.
Real min_rest_edge(const AdaptiveBody& body) {
  const TetMesh compact = body.to_tet_mesh();
  return element_lengths(compact.rest, compact.tets).min_edge;
}

Real cfl_step(Real length) {
  return time_step_floor(length, kYoungs, kPoisson, kDensity, 0.25);
}

// The probed region: top-surface rest points within 2 tool radii of the path's segment.
bool probed(const Vec3& p) {
  if (p.z() != kSize.z()) return false;
  const Real dx = p.x() < kX0 ? kX0 - p.x() : (p.x() > kX1 ? p.x() - kX1 : 0);
  return std::hypot(dx, p.y() - kY) <= 2 * kRadius;
}

// Point location in the fine mesh's rest configuration: tets bucketed on a uniform grid.
class Locator {
 public:
  Locator(const TetMesh& mesh, Real cell) : mesh_(mesh), cell_(cell) {
    for (int a = 0; a < 3; ++a)
      dims_[a] = static_cast<int>(std::ceil(kSize(a) / cell)) + 1;
    buckets_.resize(static_cast<std::size_t>(dims_[0] * dims_[1] * dims_[2]));
    for (int t = 0; t < mesh.num_tets(); ++t) {
      Vec3 lo = Vec3::Constant(std::numeric_limits<Real>::infinity()), hi = -lo;
      for (int k = 0; k < 4; ++k) {
        lo = lo.cwiseMin(Vec3(mesh.rest.row(mesh.tets(t, k))));
        hi = hi.cwiseMax(Vec3(mesh.rest.row(mesh.tets(t, k))));
      }
      const auto a = index(lo), b = index(hi);
      for (int i = a[0]; i <= b[0]; ++i)
        for (int j = a[1]; j <= b[1]; ++j)
          for (int k = a[2]; k <= b[2]; ++k)
            buckets_[bucket(i, j, k)].push_back(t);
    }
  }

  // The displacement x - rest of the fine mesh at rest point p.
  Vec3 displacement(const Points& x, const Vec3& p) const {
    const auto c = index(p);
    for (const int t : buckets_[bucket(c[0], c[1], c[2])]) {
      const std::array<int, 4> n{mesh_.tets(t, 0), mesh_.tets(t, 1), mesh_.tets(t, 2),
                                 mesh_.tets(t, 3)};
      std::array<Vec3, 4> corners;
      for (std::size_t k = 0; k < 4; ++k)
        corners[k] = mesh_.rest.row(n[k]);
      const Weights4 w = barycentric(corners, p);
      if (w.minCoeff() < -1e-9) continue;
      return interpolate_rows(x, n, w) - p;
    }
    std::fprintf(stderr, "rest point outside the fine mesh\n");
    std::exit(1);
  }

 private:
  std::array<int, 3> index(const Vec3& p) const {
    std::array<int, 3> i{};
    for (int a = 0; a < 3; ++a)
      i[a] = std::clamp(static_cast<int>(p(a) / cell_), 0, dims_[a] - 1);
    return i;
  }
  std::size_t bucket(int i, int j, int k) const {
    return static_cast<std::size_t>(i + dims_[0] * (j + dims_[1] * k));
  }
  TetMesh mesh_;
  Real cell_;
  std::array<int, 3> dims_{};
  std::vector<std::vector<int>> buckets_;
};

struct Run {
  std::string name;
  int tets_min = 0, tets_max = 0;
  Real dt = 0;
  long steps = 0;
  double step_us = 0;   // mean wall time per step, adaptation included
  double solve_us = 0;  // the same without adaptation
  double adapt_ms = 0;  // total adaptation time
  // At each sample time: rest points and displacements of the probed nodes, tets.
  std::array<std::vector<Vec3>, kSamples> rest, displacement;
  std::array<Points, kSamples> high_x;  // the fine mesh's x at the sample times (high only)
  std::array<int, kSamples> tets{};
};

Run simulate(const std::string& name, AdaptiveBody& body, bool adapt, Real fine_size, Real l_min) {
  Run run;
  run.name = name;
  body.set_fixed([](const Vec3& p) { return p.z() == 0; });
  RefinementSettings settings;
  settings.l_min = l_min;
  run.dt = cfl_step(min_rest_edge(body));
  if (adapt) run.dt = std::min(run.dt, cfl_step(l_min));
  run.tets_min = run.tets_max = body.num_tets();
  Points external;
  Real t = 0;
  std::size_t sample = 0;
  const auto start = Clock::now();
  while (t < kEnd - 1e-12) {
    const Vec3 c = tool_centre(t);
    if (adapt && run.steps % kAdaptEvery == 0) {
      const auto a = Clock::now();
      const Vec3 on_surface(c.x(), c.y(), kSize.z());
      body.refine(sphere_size_field(on_surface, 1.5 * kRadius, fine_size), settings);
      body.decimate(sphere_size_field(on_surface, 2.5 * kRadius, fine_size), 200);
      // The floor says no edge below l_min; checked rather than trusted.
      run.dt = std::min(run.dt, cfl_step(min_rest_edge(body)));
      run.adapt_ms += std::chrono::duration<double, std::milli>(Clock::now() - a).count();
      run.tets_min = std::min(run.tets_min, body.num_tets());
      run.tets_max = std::max(run.tets_max, body.num_tets());
    }
    const int n = body.num_vertex_slots();
    if (external.rows() != n) external.resize(n, 3);
    external.setZero();
    const VecX& m = body.model().masses();
    const Real k = kPenalty / (run.dt * run.dt);
    for (int i = 0; i < n; ++i) {
      if (body.inverse_masses()(i) == 0) continue;
      const Vec3 d = body.x().row(i).transpose() - c;
      const Real dist = d.norm();
      if (dist >= kRadius) continue;
      const Vec3 normal = dist > 1e-9 * kRadius ? Vec3(d / dist) : Vec3::UnitZ();
      external.row(i) = (k * m(i) * (kRadius - dist) * normal).transpose();
    }
    body.step(run.dt, kGravity, external);
    if (!body.x().allFinite()) {
      std::fprintf(stderr, "%s: not finite at t = %g s\n", name.c_str(), t);
      std::exit(1);
    }
    t += run.dt;
    ++run.steps;
    if (sample < kSamples && t >= sample_time(sample) - 1e-12) {
      run.tets[sample] = body.num_tets();
      for (int i = 0; i < body.num_vertex_slots(); ++i) {
        if (!body.mesh().vertex_alive(i) || !probed(body.mesh().point(i))) continue;
        run.rest[sample].push_back(body.mesh().point(i));
        run.displacement[sample].push_back(body.x().row(i).transpose() - body.mesh().point(i));
      }
      run.high_x[sample] = body.x();
      ++sample;
    }
  }
  const double total_us = std::chrono::duration<double, std::micro>(Clock::now() - start).count();
  run.step_us = total_us / static_cast<double>(run.steps);
  run.solve_us = (total_us - 1e3 * run.adapt_ms) / static_cast<double>(run.steps);
  return run;
}

struct Error {
  Real rms = 0, max = 0;  // relative to the largest fine displacement in the region
};

Error error_against(const Run& run, std::size_t sample, const Run& high, const Locator& fine) {
  Real scale = 0;
  for (const Vec3& u : high.displacement[sample])
    scale = std::max(scale, u.norm());
  Error e;
  Real sum = 0;
  const auto& rest = run.rest[sample];
  for (std::size_t i = 0; i < rest.size(); ++i) {
    const Vec3 ref = fine.displacement(high.high_x[sample], rest[i]);
    const Real d = (run.displacement[sample][i] - ref).norm();
    sum += d * d;
    e.max = std::max(e.max, d);
  }
  e.rms = std::sqrt(sum / static_cast<Real>(std::max<std::size_t>(1, rest.size()))) / scale;
  e.max /= scale;
  return e;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string csv = argc > 1 ? argv[1] : "results/probing.csv";
  const Vec3i coarse_cells(8, 8, 3), fine_cells(24, 24, 9);
  const Real fine_h = kSize.x() / fine_cells.x();

  AdaptiveBody high(make_box_mesh(kSize, fine_cells), mss());
  AdaptiveBody low(make_box_mesh(kSize, coarse_cells), mss());
  AdaptiveBody adaptive(make_box_mesh(kSize, coarse_cells), mss());
  // The adaptive mesh aims at the fine mesh's element size (its largest circumradius, about
  // sqrt(3)/2 of a cell) and may go down to its shortest edge, hence the same stable step.
  const Real fine_size = 0.5 * std::sqrt(3.0) * fine_h;
  const Real l_min = min_rest_edge(high);

  const Run runs[3] = {simulate("high", high, false, fine_size, l_min),
                       simulate("low", low, false, fine_size, l_min),
                       simulate("adaptive", adaptive, true, fine_size, l_min)};
  const Locator fine(high.to_tet_mesh(), fine_h);
  const Run& ref = runs[0];

  std::filesystem::path path(csv);
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
  std::ofstream out(path);
  out << "mesh,tets_min,tets_max,dt_ms,steps,step_us,solve_us,adapt_ms_total,probed_nodes_end";
  for (std::size_t s = 0; s < kTabled.size(); ++s) {
    out << ",rms_err_t" << s << ",max_err_t" << s;
  }
  out << "\n";
  std::printf(
      "block %.0f x %.0f x %.0f mm, MSS E = %.0f Pa; tool r = %.0f mm, %.0f mm deep, "
      "slides %.0f mm; error times %.3f %.3f %.3f s\n",
      kSize.x() * 1e3, kSize.y() * 1e3, kSize.z() * 1e3, kYoungs, kRadius * 1e3, kDepth * 1e3,
      (kX1 - kX0) * 1e3, sample_time(kTabled[0]), sample_time(kTabled[1]), sample_time(kTabled[2]));
  std::printf("%-9s %11s %7s %6s %8s %8s %9s %6s  %s\n", "mesh", "tets", "dt[ms]", "steps",
              "us/step", "solve_us", "adapt[ms]", "probed",
              "error vs high (rms / max, relative) at t0 t1 t2");
  const std::size_t last = kSamples - 1;
  for (const Run& r : runs) {
    char tets[32];
    std::snprintf(tets, sizeof tets, r.tets_min == r.tets_max ? "%d" : "%d-%d", r.tets_min,
                  r.tets_max);
    std::printf("%-9s %11s %7.4f %6ld %8.1f %8.1f %9.1f %6zu ", r.name.c_str(), tets, r.dt * 1e3,
                r.steps, r.step_us, r.solve_us, r.adapt_ms, r.rest[last].size());
    out << r.name << "," << r.tets_min << "," << r.tets_max << "," << r.dt * 1e3 << "," << r.steps
        << "," << r.step_us << "," << r.solve_us << "," << r.adapt_ms << "," << r.rest[last].size();
    for (const std::size_t s : kTabled) {
      const Error e = error_against(r, s, ref, fine);
      std::printf(" %.3f/%.3f", e.rms, e.max);
      out << "," << e.rms << "," << e.max;
    }
    std::printf("\n");
    out << "\n";
  }
  // The timeline (Paloc 2006's Figure 6 shows error, elements and step over the probing): a CSV
  // and two plots next to the table's CSV.
  const std::filesystem::path dir = path.has_parent_path() ? path.parent_path() : ".";
  std::ofstream timeline(dir / "probing_timeline.csv");
  timeline << "mesh,t_s,tets,rms_err,max_err\n";
  std::vector<incise::bench::Series> errors, sizes;
  for (const Run& r : runs) {
    incise::bench::Series e{r.name, {}, {}}, n{r.name, {}, {}};
    for (std::size_t s = 0; s < kSamples; ++s) {
      const Error error = error_against(r, s, ref, fine);
      timeline << r.name << "," << sample_time(s) << "," << r.tets[s] << "," << error.rms << ","
               << error.max << "\n";
      n.x.push_back(sample_time(s));
      n.y.push_back(r.tets[s]);
      if (&r == &ref) continue;
      e.x.push_back(sample_time(s));
      e.y.push_back(error.rms);
    }
    if (&r != &ref) errors.push_back(std::move(e));
    sizes.push_back(std::move(n));
  }
  std::ofstream(dir / "probing_error.svg")
      << incise::bench::linear_svg(errors, {"Probing: error against the high-resolution mesh",
                                            "time [s] (push to 0.15 s, slide to 0.40 s)",
                                            "rms error / peak displacement, probed region"});
  std::ofstream(dir / "probing_tets.svg")
      << incise::bench::linear_svg(sizes, {"Probing: number of tetrahedra", "time [s]", "tets"});
  std::printf("written: %s, %s, %s, %s\n", path.string().c_str(),
              (dir / "probing_timeline.csv").string().c_str(),
              (dir / "probing_error.svg").string().c_str(),
              (dir / "probing_tets.svg").string().c_str());
  return 0;
}
