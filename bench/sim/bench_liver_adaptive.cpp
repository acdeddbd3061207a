// The liver benchmark with adaptivity: a 20 cm liver-like organ (Paloc 2006's liver: 1,576
// nodes, 5,983 tets, E 4 kPa, density 1050 kg/m^3; nu 0.3 here, as in bench_liver), its flat
// side held, stroked by a scripted tool, simulated four ways with the same model:
//   fine       a fine mesh (about 5k tets), every node integrated: the reference;
//   active     the fine mesh with the active region (ActiveExplicitStepper);
//   coarse     a coarse mesh, every node integrated;
//   adaptive   the coarse mesh refined near the tool to the fine mesh's size (l_min = the fine
//              mesh's smallest altitude, so the same time step) and decimated behind it.
// Each runs symplectic Euler at its stable step (stable_time_step; for the adaptive mesh the floor
// time_step_floor(min(l_min, the coarse mesh's smallest altitude)), which refinement and
// decimation both keep). Measured: steps per second (adaptation included; one core), tets, and
// the error in the probed region against the fine run: the displacement field of each run
// sampled at the rest points of the fine mesh's nodes within 3 cm of the tool path (barycentric in
// the run's rest tet holding the point, or the nearest tet for points just outside a coarser
// surface), every 0.02 s, relative to the fine run's peak displacement there.
//
// The tool is force-driven so that every mesh sees the same load: 0.05 N spread over the nodes
// within 1 cm of a point 5 mm under the upper surface, weighted by node mass and a hat kernel
// (a body-force density, which every mesh integrates alike), moved along x at y = 0 from -L/4 to
// +L/4 over 0.4 s, then released until 0.5 s.
// Run from anywhere (about a minute with -O3):
//   bench_liver_adaptive [corotational|mss] [fine cell m = 0.0085] [coarse cell m = 0.017]

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sim/mesh/cgal/implicit_shape.h"
#include "sim/mesh/cgal/mesh_generation.h"
#include "sim/remesh/adaptive_body.h"
#include "sim/remesh/size_field.h"
#include "sim/remesh/state_transfer.h"
#include "sim/scene/scene_run.h"
#include "sim/solve/active_region.h"
#include "sim/solve/stable_time_step.h"
#include "sim/solve/symplectic_euler.h"

using namespace incise::sim;
using namespace incise::sim::remesh;
using Clock = std::chrono::steady_clock;

namespace {

constexpr Real kLength = 0.2;  // [m]
constexpr Real kYoungs = 4e3, kPoisson = 0.3, kDensity = 1050, kDamping = 0.3;
constexpr Real kForce = 0.05;        // [N]
constexpr Real kLoadRadius = 0.01;   // [m]
constexpr Real kLoadDepth = 0.005;   // below the upper surface [m]
constexpr Real kStrokeEnd = 0.4;     // [s]
constexpr Real kEnd = 0.5;           // [s]
constexpr Real kSampleEvery = 0.02;  // [s]
constexpr Real kRegionRadius = 0.03;
constexpr int kAdaptEvery = 10;  // steps
// Refinement within 1.5 cm of the load point, decimation beyond 2.5 cm (hysteresis).
constexpr Real kRefineRadius = 0.015, kKeepRadius = 0.025;

MaterialModel g_model = MaterialModel::corotational;

ModelFactory factory() {
  Scene scene;
  scene.material.model = g_model;
  scene.material.youngs_modulus = kYoungs;
  scene.material.poisson_ratio = kPoisson;
  scene.material.density = kDensity;
  scene.material.damping = kDamping;
  return [scene](const TetMesh& mesh) { return make_model(scene, mesh); };
}

TetMesh liver_mesh(const LobedOrgan& liver, Real cell) {
  MeshingCriteria criteria;
  criteria.cell_size = cell;
  criteria.facet_size = cell;
  criteria.facet_distance = cell / 8;
  TetMesh mesh = mesh_implicit(liver, implicit_extent(liver), criteria);
  mesh.labels.setZero();
  return mesh;
}

// The height of the upper surface along the path (y = 0), from the fine mesh's rest nodes: the
// highest node within 5 mm of (x, 0), on a 1 mm grid in x.
class UpperSurface {
 public:
  explicit UpperSurface(const Points& rest) {
    for (int i = 0; i <= kSamples; ++i) {
      const Real x = x_of(i);
      Real top = -std::numeric_limits<Real>::infinity();
      for (Eigen::Index n = 0; n < rest.rows(); ++n) {
        if (std::hypot(rest(n, 0) - x, rest(n, 1)) < 0.005) top = std::max(top, rest(n, 2));
      }
      z_[static_cast<std::size_t>(i)] = top;
    }
  }
  Real at(Real x) const {
    const Real s = std::clamp((x + kLength / 4) / (kLength / 2), 0.0, 1.0) * kSamples;
    const int i = std::min(static_cast<int>(s), kSamples - 1);
    const Real f = s - i;
    return (1 - f) * z_[static_cast<std::size_t>(i)] + f * z_[static_cast<std::size_t>(i) + 1];
  }

 private:
  static constexpr int kSamples = 100;
  static Real x_of(int i) { return -kLength / 4 + kLength / 2 * i / kSamples; }
  std::array<Real, kSamples + 1> z_{};
};

// The load point at time t (nullopt once released).
std::optional<Vec3> load_point(const UpperSurface& top, Real t) {
  if (t >= kStrokeEnd) return std::nullopt;
  const Real x = -kLength / 4 + t / kStrokeEnd * kLength / 2;
  return Vec3(x, 0, top.at(x) - kLoadDepth);
}

// external = the load, spread over the nodes (moving ones: inverse mass > 0) whose rest point is
// within kLoadRadius of p, by mass times the hat 1 - r / kLoadRadius.
void apply_load(const Points& rest, const VecX& masses, const VecX& inverse_masses, const Vec3& p,
                Points& external) {
  Real total = 0;
  for (Eigen::Index i = 0; i < rest.rows(); ++i) {
    if (inverse_masses(i) == 0) continue;
    const Real r = (rest.row(i).transpose() - p).norm();
    if (r < kLoadRadius) total += masses(i) * (1 - r / kLoadRadius);
  }
  if (total == 0) return;
  for (Eigen::Index i = 0; i < rest.rows(); ++i) {
    if (inverse_masses(i) == 0) continue;
    const Real r = (rest.row(i).transpose() - p).norm();
    if (r < kLoadRadius) external(i, 2) -= kForce * masses(i) * (1 - r / kLoadRadius) / total;
  }
}

struct Run {
  std::string name;
  int tets_min = 0, tets_max = 0;
  Real dt = 0;
  long steps = 0;
  double seconds = 0;            // stepping and adaptation
  double adapt_seconds = 0;      // adaptation alone
  double active_tets = 0;        // mean (active run)
  std::vector<double> adapt_ms;  // each adaptation call (refine + decimate)
  // At each sample: the displacement at the region's rest points.
  std::vector<std::vector<Vec3>> samples;
};

struct Region {
  std::vector<Vec3> rest;  // the fine mesh's nodes within kRegionRadius of the path
};

// A run on an AdaptiveBody (fine, coarse, adaptive).
Run run_body(const std::string& name, const TetMesh& mesh, const LobedOrgan& liver,
             const UpperSurface& top, const Region& region, bool adapt, Real fine_size,
             Real l_min) {
  Run run;
  run.name = name;
  AdaptiveBody body(mesh, factory());
  const Real flat = liver.flat_side_z + 1e-4;
  body.set_fixed([flat](const Vec3& p) { return p.z() < flat; });
  run.dt = stable_time_step(mesh, kYoungs, kPoisson, kDensity);
  RefinementSettings settings;
  if (adapt) {
    const Real floor = std::min(l_min, element_lengths(mesh.rest, mesh.tets).min_altitude);
    run.dt = time_step_floor(floor, kYoungs, kPoisson, kDensity);
    settings.l_min = l_min;
    settings.floor_altitudes = true;
    body.set_decimation_floor(floor);
  }
  run.tets_min = run.tets_max = body.num_tets();
  Points external;
  Real t = 0;
  Real next_sample = 0;
  const auto start = Clock::now();
  double outside = 0;  // sampling, not simulation
  while (t < kEnd - 1e-12) {
    const std::optional<Vec3> p = load_point(top, t);
    if (adapt && run.steps % kAdaptEvery == 0) {
      const auto a = Clock::now();
      if (p) {
        settings.region = region_hint_of(*p, kRefineRadius);
        body.refine(sphere_size_field(*p, kRefineRadius, fine_size), settings);
        body.decimate(sphere_size_field(*p, kKeepRadius, fine_size), 200);
      } else {
        const SizeField nowhere = [](const Vec3&) { return std::numeric_limits<Real>::infinity(); };
        body.decimate(nowhere, 200);
      }
      const double call = std::chrono::duration<double>(Clock::now() - a).count();
      run.adapt_seconds += call;
      run.adapt_ms.push_back(1e3 * call);
      run.tets_min = std::min(run.tets_min, body.num_tets());
      run.tets_max = std::max(run.tets_max, body.num_tets());
    }
    const int n = body.num_vertex_slots();
    if (external.rows() != n) external.resize(n, 3);
    external.setZero();
    if (p) {
      apply_load(body.slot_view().rest, body.model().masses(), body.inverse_masses(), *p, external);
    }
    body.step(run.dt, Vec3::Zero(), external);
    t += run.dt;
    ++run.steps;
    if (t >= next_sample) {
      const auto s = Clock::now();
      if (!body.x().allFinite()) {
        std::fprintf(stderr, "%s: not finite at t = %g s\n", name.c_str(), t);
        std::exit(1);
      }
      std::vector<Vec3> u;
      for (const Vec3& q : region.rest) {
        u.push_back(displacement_at(body.slot_view().rest, body.x(), body.slot_view().tets,
                                    &body.tet_alive(), q));
      }
      run.samples.push_back(std::move(u));
      next_sample += kSampleEvery;
      outside += std::chrono::duration<double>(Clock::now() - s).count();
    }
  }
  run.seconds = std::chrono::duration<double>(Clock::now() - start).count() - outside;
  return run;
}

// The fine mesh with the active region.
Run run_active(const TetMesh& mesh, const LobedOrgan& liver, const UpperSurface& top,
               const Region& region) {
  Run run;
  run.name = "active";
  std::vector<int> fixed;
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    if (mesh.rest(i, 2) < liver.flat_side_z + 1e-4) fixed.push_back(i);
  }
  ActiveRegionSettings settings;
  settings.wake_force = 5e-5;
  settings.sleep_force = settings.wake_force / 4;
  settings.sleep_speed = 1e-4;
  settings.sleep_frames = 20;
  ActiveExplicitStepper stepper(mesh, factory(), settings, fixed);
  const std::unique_ptr<Model> model = factory()(mesh);
  VecX inverse = model->masses().cwiseInverse();
  for (const int i : fixed)
    inverse(i) = 0;
  run.dt = stable_time_step(mesh, kYoungs, kPoisson, kDensity);
  run.tets_min = run.tets_max = mesh.num_tets();
  Points x = mesh.x, v = mesh.v, external(mesh.num_nodes(), 3);
  Real t = 0, next_sample = 0;
  long active_tets = 0;
  const auto start = Clock::now();
  double outside = 0;
  while (t < kEnd - 1e-12) {
    external.setZero();
    if (const std::optional<Vec3> p = load_point(top, t)) {
      apply_load(mesh.rest, model->masses(), inverse, *p, external);
    }
    stepper.step(run.dt, Vec3::Zero(), external, x, v);
    active_tets += stepper.metrics().active_tets;
    t += run.dt;
    ++run.steps;
    if (t >= next_sample) {
      const auto s = Clock::now();
      std::vector<Vec3> u;
      for (const Vec3& q : region.rest)
        u.push_back(displacement_at(mesh.rest, x, mesh.tets, nullptr, q));
      run.samples.push_back(std::move(u));
      next_sample += kSampleEvery;
      outside += std::chrono::duration<double>(Clock::now() - s).count();
    }
  }
  run.seconds = std::chrono::duration<double>(Clock::now() - start).count() - outside;
  run.active_tets = static_cast<double>(active_tets) / static_cast<double>(run.steps);
  return run;
}

// The value below which the fraction q of the samples lie (nearest rank).
double quantile(std::vector<double> samples, double q) {
  if (samples.empty()) return 0;
  std::sort(samples.begin(), samples.end());
  const std::size_t rank =
      static_cast<std::size_t>(q * static_cast<double>(samples.size() - 1) + 0.5);
  return samples[std::min(rank, samples.size() - 1)];
}

struct Error {
  Real rms = 0, max = 0;  // relative to the fine run's peak displacement in the region
};

Error error_against(const Run& run, const Run& fine) {
  Real peak = 0;
  for (const auto& sample : fine.samples) {
    for (const Vec3& u : sample)
      peak = std::max(peak, u.norm());
  }
  Error e;
  Real sum = 0;
  long count = 0;
  const std::size_t samples = std::min(run.samples.size(), fine.samples.size());
  for (std::size_t s = 0; s < samples; ++s) {
    for (std::size_t i = 0; i < fine.samples[s].size(); ++i) {
      const Real d = (run.samples[s][i] - fine.samples[s][i]).norm();
      sum += d * d;
      ++count;
      e.max = std::max(e.max, d);
    }
  }
  e.rms = std::sqrt(sum / static_cast<Real>(std::max(1L, count))) / peak;
  e.max /= peak;
  return e;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 1 && std::strcmp(argv[1], "mss") == 0) g_model = MaterialModel::mass_spring;
  const Real fine_cell = argc > 2 ? std::atof(argv[2]) : 0.0085;
  const Real coarse_cell = argc > 3 ? std::atof(argv[3]) : 0.017;
  const LobedOrgan liver = liver_like_organ(Vec3::Zero(), kLength);
  const TetMesh fine = liver_mesh(liver, fine_cell);
  const TetMesh coarse = liver_mesh(liver, coarse_cell);
  const UpperSurface top(fine.rest);

  Region region;
  for (int i = 0; i < fine.num_nodes(); ++i) {
    const Vec3 q = fine.rest.row(i).transpose();
    const Real dx = std::max({-kLength / 4 - q.x(), 0.0, q.x() - kLength / 4});
    if (std::hypot(dx, q.y()) < kRegionRadius && q.z() > top.at(q.x()) - kRegionRadius) {
      region.rest.push_back(q);
    }
  }
  // The adaptive mesh aims at the fine mesh's size (its cell size bounds the circumradius) with
  // the fine mesh's smallest altitude as l_min: the same stable step as the fine mesh.
  const Real l_min = element_lengths(fine.rest, fine.tets).min_altitude;
  std::printf(
      "liver-like organ %.0f cm, %s, E %.0f Pa, nu %.2f: fine %d nodes / %d tets, coarse %d / "
      "%d; probed region %zu fine nodes; l_min %.2f mm\n",
      100 * kLength, g_model == MaterialModel::mass_spring ? "mass-spring" : "corotational",
      kYoungs, kPoisson, fine.num_nodes(), fine.num_tets(), coarse.num_nodes(), coarse.num_tets(),
      region.rest.size(), 1e3 * l_min);

  std::vector<Run> runs;
  runs.push_back(run_body("fine", fine, liver, top, region, false, fine_cell, l_min));
  runs.push_back(run_active(fine, liver, top, region));
  runs.push_back(run_body("coarse", coarse, liver, top, region, false, fine_cell, l_min));
  runs.push_back(run_body("adaptive", coarse, liver, top, region, true, fine_cell, l_min));

  std::printf(
      "\n| run | tets | dt [ms] | steps/s (one core) | adaptation [%% of time] | error rms / max "
      "(of peak %s) |\n|---|---|---|---|---|---|\n",
      "displacement");
  for (const Run& r : runs) {
    const Error e = error_against(r, runs[0]);
    const std::string tets =
        r.name == "active"         ? std::to_string(static_cast<int>(r.active_tets)) + " active"
        : r.tets_min == r.tets_max ? std::to_string(r.tets_min)
                                   : std::to_string(r.tets_min) + "-" + std::to_string(r.tets_max);
    std::printf("| %s | %s | %.3f | %.0f | %.0f | %s |\n", r.name.c_str(), tets.c_str(), 1e3 * r.dt,
                static_cast<double>(r.steps) / r.seconds, 100 * r.adapt_seconds / r.seconds,
                r.name == "fine" ? "reference"
                                 : (std::to_string(e.rms).substr(0, 5) + " / " +
                                    std::to_string(e.max).substr(0, 5))
                                       .c_str());
  }
  const Run& adaptive = runs.back();
  std::printf(
      "\nadaptation calls (every %d steps, refine + decimate around the moving load): %zu, "
      "median %.3f ms, p99 %.3f ms, max %.3f ms\n",
      kAdaptEvery, adaptive.adapt_ms.size(), quantile(adaptive.adapt_ms, 0.5),
      quantile(adaptive.adapt_ms, 0.99), quantile(adaptive.adapt_ms, 1.0));
  return 0;
}
