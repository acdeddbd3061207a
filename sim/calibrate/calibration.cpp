#include "sim/calibrate/calibration.h"

#include <chrono>
#include <cmath>
#include <random>

#include "sim/scene/node_selection.h"
#include "sim/scene/scene_error.h"

namespace incise::sim::calibrate {
namespace {

Real mean_edge_length(const TetMesh& mesh) {
  static constexpr int kEdges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
  Real sum = 0;
  for (int t = 0; t < mesh.num_tets(); ++t) {
    for (const auto& e : kEdges) {
      sum += (row3(mesh.rest, mesh.tets(t, e[0])) - row3(mesh.rest, mesh.tets(t, e[1]))).norm();
    }
  }
  return mesh.num_tets() > 0 ? sum / (6 * mesh.num_tets()) : 0;
}

// The data attached to the body (attach_probe_data), checked to move somewhere.
std::vector<ProbeExperiment> experiments_of(const ProbeData& data, const TetMesh& mesh,
                                            const std::vector<char>& fixed,
                                            Real max_contact_distance) {
  std::vector<ProbeExperiment> experiments =
      attach_probe_data(data, mesh.rest, fixed,
                        max_contact_distance > 0 ? max_contact_distance : mean_edge_length(mesh));
  Real sum = 0;
  for (const ProbeExperiment& e : experiments)
    sum += e.measured.squaredNorm();
  if (!(sum > 0)) {
    throw CalibrationError("the probe never moves in the data: nothing tells the stiffness");
  }
  return experiments;
}

// The body, its experiments and the misfit's scale, ready to evaluate points of parameters.
struct Setup {
  Setup(const std::vector<char>& fixed, const TetMesh& mesh, const ProbeData& data,
        const MaterialParameters& parameters, Real max_contact_distance)
      : parameters(parameters),
        response(parameters.masses(), fixed, data.step,
                 experiments_of(data, mesh, fixed, max_contact_distance)) {
    Real sum = 0;
    for (const ProbeExperiment& e : response.experiments()) {
      sum += e.measured.squaredNorm();
      data_size += static_cast<int>(e.measured.size());
    }
    scale = 1 / std::sqrt(sum);
  }

  // The residuals at z: the data's, then the prior's.
  bool residuals(const VecX& z, VecX& r) {
    if (!parameters.assemble(z, stiffness, damping)) return false;
    if (!response.simulate(stiffness, damping, simulated)) return false;
    r.resize(data_size + parameters.prior_size());
    Eigen::Index at = 0;
    for (std::size_t e = 0; e < simulated.size(); ++e) {
      const Points& measured = response.experiments()[e].measured;
      for (Eigen::Index k = 0; k < measured.rows(); ++k) {
        for (int a = 0; a < 3; ++a)
          r[at++] = scale * (simulated[e](k, a) - measured(k, a));
      }
    }
    parameters.prior(z, r.segment(at, parameters.prior_size()));
    return true;
  }

  const MaterialParameters& parameters;
  LinearResponse response;
  Real scale = 1;
  int data_size = 0;
  Triplets stiffness, damping;
  std::vector<Points> simulated;
};

Real data_misfit(const VecX& r, int data_size) {
  return r.head(data_size).squaredNorm();
}

}  // namespace

std::vector<char> fixed_nodes(const Scene& scene, const TetMesh& mesh) {
  try {
    return held_at_rest(scene, mesh);
  } catch (const SceneError& e) {
    throw CalibrationError(e.what());
  }
}

void check_probe_data(const Scene& scene, const TetMesh& mesh, const ProbeData& data,
                      Real max_contact_distance) {
  experiments_of(data, mesh, fixed_nodes(scene, mesh), max_contact_distance);
}

CalibrationResult calibrate(const Scene& scene, const TetMesh& mesh, const ProbeData& data,
                            const CalibrationOptions& options) {
  if (!(options.smoothing >= 0)) throw CalibrationError("smoothing must be >= 0");
  if (options.max_evaluations < 1) throw CalibrationError("the budget must be at least 1");
  const MaterialParameters parameters =
      options.parameters == ParameterKind::node_moduli
          ? MaterialParameters::node_moduli(scene, mesh, options.smoothing)
          : MaterialParameters::label_materials(scene, mesh);
  Setup setup(fixed_nodes(scene, mesh), mesh, data, parameters, options.max_contact_distance);

  Problem problem;
  problem.start = parameters.start();
  problem.lower = parameters.lower();
  problem.upper = parameters.upper();
  problem.residuals = [&](const VecX& z, VecX& r) { return setup.residuals(z, r); };
  OptimiserSettings settings;
  settings.method = options.method;
  settings.max_evaluations = options.max_evaluations;
  settings.seed = options.seed;
  settings.population = options.population;
  settings.initial_step = options.initial_step;
  settings.cancel = options.cancel;
  settings.progress = options.progress;

  CalibrationResult result;
  result.parameters = options.parameters;
  const auto began = std::chrono::steady_clock::now();
  result.search = minimise(problem, settings);
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count();

  VecX r;
  std::vector<Points> start_curves;
  if (setup.residuals(problem.start, r)) {
    result.start_misfit = data_misfit(r, setup.data_size);
    start_curves = setup.simulated;
  }
  if (!setup.residuals(result.search.best, r)) {
    throw CalibrationError("the calibrated constants cannot be simulated");
  }
  result.misfit = data_misfit(r, setup.data_size);
  const VecX& z = result.search.best;
  for (int i = 0; i < parameters.size(); ++i) {
    CalibratedValue v;
    v.name = parameters.names()[static_cast<std::size_t>(i)];
    v.owner = parameters.owner(i);
    v.start = parameters.value(i, problem.start);
    v.value = parameters.value(i, z);
    const Real spread = result.search.spread.size() > i ? result.search.spread[i] : 0;
    v.spread = parameters.is_modulus(i) ? v.value * spread : spread;  // d E = E d ln E
    result.values.push_back(v);
  }
  result.calibrated = parameters.scene_with(z);

  const auto& experiments = setup.response.experiments();
  for (std::size_t e = 0; e < experiments.size(); ++e) {
    const ProbeExperiment& x = experiments[e];
    const ProbeContact& contact = data.contacts[e];
    const Vec3 direction = contact.samples.front().direction;
    ContactFit fit;
    fit.contact_id = x.contact_id;
    fit.node = x.node;
    fit.distance = x.distance;
    for (Eigen::Index k = 0; k < x.measured.rows(); ++k) {
      fit.time.push_back(contact.samples[static_cast<std::size_t>(k + 1)].time);
      fit.force.push_back(row3(x.force, static_cast<int>(k)).dot(direction));
      fit.measured.push_back(row3(x.measured, static_cast<int>(k)).dot(direction));
      fit.fitted.push_back(row3(setup.simulated[e], static_cast<int>(k)).dot(direction));
      if (!start_curves.empty()) {
        fit.start.push_back(row3(start_curves[e], static_cast<int>(k)).dot(direction));
      }
    }
    result.fits.push_back(std::move(fit));
  }
  return result;
}

ProbeData simulate_probe_data(const Scene& scene, const TetMesh& mesh,
                              const MaterialParameters& parameters, const VecX& z,
                              const ProbeData& data) {
  const std::vector<char> fixed = fixed_nodes(scene, mesh);
  LinearResponse response(parameters.masses(), fixed, data.step,
                          attach_probe_data(data, mesh.rest, fixed, mean_edge_length(mesh)));
  Triplets stiffness, damping;
  std::vector<Points> simulated;
  if (!parameters.assemble(z, stiffness, damping) ||
      !response.simulate(stiffness, damping, simulated)) {
    throw CalibrationError("the reference constants cannot be simulated");
  }
  ProbeData out = data;
  for (std::size_t e = 0; e < out.contacts.size(); ++e) {
    auto& samples = out.contacts[e].samples;
    for (std::size_t k = 1; k < samples.size(); ++k) {
      samples[k].position = samples[0].position + row3(simulated[e], static_cast<int>(k - 1));
    }
  }
  return out;
}

ProbeData with_position_noise(ProbeData data, Real fraction, std::uint64_t seed) {
  Real sum = 0;
  int n = 0;
  for (const ProbeContact& c : data.contacts) {
    for (const ProbeSample& s : c.samples) {
      sum += (s.position - c.samples.front().position).squaredNorm();
      ++n;
    }
  }
  const Real sigma = n > 0 ? fraction * std::sqrt(sum / n / 3) : 0;
  if (!(sigma > 0)) return data;
  std::mt19937_64 random(seed);
  std::normal_distribution<Real> normal(0, sigma);
  for (ProbeContact& c : data.contacts) {
    for (std::size_t k = 1; k < c.samples.size(); ++k) {
      for (int a = 0; a < 3; ++a)
        c.samples[k].position[a] += normal(random);
    }
  }
  return data;
}

}  // namespace incise::sim::calibrate
