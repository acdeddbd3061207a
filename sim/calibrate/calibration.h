#pragma once
// Calibration (issue 26, seed 004; docs/calibration.md): fits a scene's material constants to
// force-displacement data. The data's forces push the body (its linearisation at rest, stepped
// as the data is sampled: linear_response.h) and the misfit is the squared difference between
// the simulated and the measured probe displacements, relative to the measured ones:
//   misfit = sum_contacts sum_samples |u_sim - u_measured|^2 / sum |u_measured|^2
// (plus the smoothness prior of node moduli, material_parameters.h).

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "sim/calibrate/linear_response.h"
#include "sim/calibrate/material_parameters.h"
#include "sim/calibrate/optimisers.h"
#include "sim/calibrate/probe_data.h"
#include "sim/mesh/tet_mesh.h"
#include "sim/scene/scene.h"

namespace incise::sim::calibrate {

struct CalibrationOptions {
  Method method = Method::lm;
  ParameterKind parameters = ParameterKind::label_materials;
  Real smoothing = 1e-5;          // node moduli's prior weight (material_parameters.h), >= 0
  int max_evaluations = 2000;     // the budget
  std::uint64_t seed = 1;         // ga, cmaes
  int population = 0;             // ga, cmaes (0: the method's default)
  Real initial_step = 0.3;        // in ln E
  Real max_contact_distance = 0;  // [m]; 0: the mesh's mean edge length
  const std::atomic<bool>* cancel = nullptr;
  std::function<void(const Progress&)> progress;
};

// One contact's curves, along the direction the probe pushes (its first sample's): what the
// data measured and what the model simulates before and after calibration.
struct ContactFit {
  int contact_id = 0;
  int node = 0;
  Real distance = 0;           // probe start to node [m]
  std::vector<Real> time;      // [s], the samples after the first
  std::vector<Real> force;     // [N] along the direction
  std::vector<Real> measured;  // displacement along the direction [m]
  std::vector<Real> start;     // simulated with the scene's constants [m]
  std::vector<Real> fitted;    // simulated with the calibrated ones [m]
};

struct CalibratedValue {
  std::string name;  // "E[0]", "nu[0]"
  int owner = 0;     // node or label
  Real start = 0;    // the scene's value (Pa for E)
  Real value = 0;    // calibrated
  Real spread = 0;   // its spread in the same unit (optimisers.h)
};

struct CalibrationResult {
  ParameterKind parameters = ParameterKind::label_materials;
  OptimiserResult search;
  std::vector<CalibratedValue> values;
  Scene calibrated;  // the scene with the calibrated constants (per label)
  std::vector<ContactFit> fits;
  Real start_misfit = 0;  // the data term alone, relative (above)
  Real misfit = 0;
  Real seconds = 0;  // wall time of the search
};

// The nodes every "fix": "xyz" constraint of scene holds (held_at_rest, node_selection.h).
// Throws CalibrationError for a constraint that holds only some axes, prescribes a displacement
// (calibration starts from rest) or selects no node.
std::vector<char> fixed_nodes(const Scene& scene, const TetMesh& mesh);

// Checks, without simulating, that the body can take the data: every contact near a free node,
// the probe moving somewhere. Throws CalibrationError as calibrate does.
void check_probe_data(const Scene& scene, const TetMesh& mesh, const ProbeData& data,
                      Real max_contact_distance = 0);

// Throws CalibrationError for data the body cannot take (no contact, a fixed node, a probe that
// never moves) and for options out of range.
CalibrationResult calibrate(const Scene& scene, const TetMesh& mesh, const ProbeData& data,
                            const CalibrationOptions& options);

// What the scene's model with constants z of parameters gives for data's pushes (the same forces
// and starting points): data with each position replaced by the simulated one. For synthetic
// experiments and tests. Throws CalibrationError as calibrate.
ProbeData simulate_probe_data(const Scene& scene, const TetMesh& mesh,
                              const MaterialParameters& parameters, const VecX& z,
                              const ProbeData& data);

// data with Gaussian noise added to every coordinate of every position after each contact's first:
// a standard deviation of `fraction` times the root-mean-square displacement, from a generator
// seeded with `seed` (the same noise for the same seed). For synthetic experiments.
ProbeData with_position_noise(ProbeData data, Real fraction, std::uint64_t seed);

}  // namespace incise::sim::calibrate
