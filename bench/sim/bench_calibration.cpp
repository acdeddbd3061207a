// bench_calibration: seed 004's spring-calibration experiment (sim/calibrate/cube_experiment.h).
// Data from a reference mass-spring cube with known per-node moduli; each method starts from a
// homogeneous 2.4 kPa and reconstructs the 125 node moduli from the five pushes. Prints, per
// reference field and method, the largest and mean modulus error, the error by distance from the
// probed nodes, the relative misfit, the evaluations and the time. Then one modulus for the whole
// cube by each method, the noise study (Levenberg-Marquardt on data with Gaussian noise) and the
// mass-spring cube calibrated to behave like the linear FEM cube (one modulus).
// Usage: bench_calibration [--quick]   (--quick: budgets of 400 simulations, for a smoke run)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "sim/calibrate/calibration.h"
#include "sim/calibrate/cube_experiment.h"

using namespace incise::sim;
using namespace incise::sim::calibrate;

namespace {

constexpr Real kStartModulus = 2400;

struct Errors {
  Real largest = 0, mean = 0;
  Real band[3] = {0, 0, 0};  // largest error at 0, <= 2.5 mm, farther from a probed node
};

Errors modulus_errors(const CalibrationResult& result, const VecX& truth, const TetMesh& mesh,
                      const std::vector<int>& probed) {
  Errors e;
  int counted = 0;
  for (const CalibratedValue& v : result.values) {
    const Real reference = truth[v.owner];
    const Real error = std::abs(v.value - reference) / reference;
    e.largest = std::max(e.largest, error);
    e.mean += error;
    ++counted;
    Real nearest = 1;
    for (const int p : probed) {
      nearest = std::min(nearest, (row3(mesh.rest, v.owner) - row3(mesh.rest, p)).norm());
    }
    const int band = nearest < 1e-9 ? 0 : nearest <= 0.0026 ? 1 : 2;
    e.band[band] = std::max(e.band[band], error);
  }
  e.mean /= counted;
  return e;
}

}  // namespace

int main(int argc, char** argv) {
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  const CubeExperiment reference_cube = seed004_cube(kCubeModulus);
  const CubeExperiment cube = seed004_cube(kStartModulus);
  const TetMesh& mesh = cube.mesh;
  const MaterialParameters reference =
      MaterialParameters::node_moduli(reference_cube.scene, mesh, 0);
  std::vector<int> probed;
  {
    const std::vector<char> fixed = fixed_nodes(cube.scene, mesh);
    for (const auto& e : attach_probe_data(cube.pushes, mesh.rest, fixed, 1e-6)) {
      probed.push_back(e.node);
    }
  }
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // each line as it is printed, also into a file
  std::printf(
      "bench_calibration: seed 004's cube, 1 cm, %d nodes, %d tets, %d springs, five pushes of "
      "%g N for %g s (%d samples); node moduli from a homogeneous %.1f kPa\n",
      mesh.num_nodes(), mesh.num_tets(), static_cast<int>(reference.spring_count()), kCubeForce,
      kCubePushTime, kCubeSamples, kStartModulus / 1000);

  // The reference fields: the seed's homogeneous one, and one graded along the height
  // (2.4 kPa at the fixed bottom to 4.8 kPa at the top) with a stiff spot near a side face.
  struct Field {
    const char* name;
    VecX moduli;
  };
  VecX homogeneous = VecX::Constant(mesh.num_nodes(), kCubeModulus);
  VecX graded(mesh.num_nodes());
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    const Vec3 p = row3(mesh.rest, i) / kCubeEdge;
    graded[i] = 2400 * (1 + p.z()) *
                (1 + 0.5 * std::exp(-((p - Vec3(0.25, 0.5, 0.5)).squaredNorm()) / 0.05));
  }
  const Field fields[] = {{"homogeneous 3.6 kPa (seed 004)", homogeneous},
                          {"graded 2.4-4.8 kPa, stiff spot", graded}};

  std::printf("\n%-32s %-6s %9s %9s %9s %9s %9s %11s %11s %7s %8s\n", "reference", "method",
              "largest", "mean", "probed", "<=2.5mm", "farther", "misfit0", "misfit", "evals",
              "time");
  for (const Field& field : fields) {
    VecX z(mesh.num_nodes());
    for (int i = 0; i < mesh.num_nodes(); ++i)
      z[i] = std::log(field.moduli[i]);
    const ProbeData data = simulate_probe_data(cube.scene, mesh, reference, z, cube.pushes);
    for (const Method method : {Method::ga, Method::cmaes, Method::lm}) {
      CalibrationOptions options;
      options.method = method;
      options.parameters = ParameterKind::node_moduli;
      options.max_evaluations = method == Method::lm ? (quick ? 400 : 2000) : (quick ? 400 : 4000);
      options.seed = 4;
      const CalibrationResult result = calibrate::calibrate(cube.scene, mesh, data, options);
      const Errors e = modulus_errors(result, field.moduli, mesh, probed);
      std::printf("%-32s %-6s %8.2f%% %8.2f%% %8.2f%% %8.2f%% %8.2f%% %11.3g %11.3g %7d %7.1fs\n",
                  field.name, std::string(method_name(method)).c_str(), 100 * e.largest,
                  100 * e.mean, 100 * e.band[0], 100 * e.band[1], 100 * e.band[2],
                  result.start_misfit, result.misfit, result.search.evaluations, result.seconds);
      std::fflush(stdout);
    }
  }

  // The well-posed question: one modulus for the whole cube (per label), each method.
  std::printf("\none modulus (per label), homogeneous 3.6 kPa reference, from 2.4 kPa:\n");
  std::printf("%-6s %12s %11s %7s %8s\n", "method", "error", "misfit", "evals", "time");
  {
    const VecX z = homogeneous.array().log();
    const ProbeData data = simulate_probe_data(cube.scene, mesh, reference, z, cube.pushes);
    for (const Method method : {Method::ga, Method::cmaes, Method::lm}) {
      CalibrationOptions options;
      options.method = method;
      options.max_evaluations = 400;
      options.seed = 4;
      const CalibrationResult result = calibrate::calibrate(cube.scene, mesh, data, options);
      std::printf("%-6s %11.2g%% %11.3g %7d %7.1fs\n", std::string(method_name(method)).c_str(),
                  100 * std::abs(result.values[0].value - kCubeModulus) / kCubeModulus,
                  result.misfit, result.search.evaluations, result.seconds);
      std::fflush(stdout);
    }
  }

  std::printf("\nnoise (Gaussian, a fraction of the rms displacement, every coordinate), lm:\n");
  std::printf("%-32s %9s %9s %9s %11s\n", "reference", "noise", "largest", "mean", "misfit");
  {
    VecX z = homogeneous.array().log();
    const ProbeData clean = simulate_probe_data(cube.scene, mesh, reference, z, cube.pushes);
    for (const Real noise : {0.0, 0.01, 0.05}) {
      CalibrationOptions options;
      options.method = Method::lm;
      options.parameters = ParameterKind::node_moduli;
      options.max_evaluations = quick ? 400 : 2000;
      const CalibrationResult result =
          calibrate::calibrate(cube.scene, mesh, with_position_noise(clean, noise, 7), options);
      const Errors e = modulus_errors(result, homogeneous, mesh, probed);
      std::printf("%-32s %8.1f%% %8.2f%% %8.2f%% %11.3g\n", fields[0].name, 100 * noise,
                  100 * e.largest, 100 * e.mean, result.misfit);
      std::fflush(stdout);
    }
  }

  // The mass-spring cube calibrated (one modulus, lm) to behave like the linear FEM cube of the
  // same mesh and E under the same pushes, for several Poisson's ratios.
  std::printf("\nmass-spring cube fitted to the linear FEM cube (E = %.1f kPa), lm:\n",
              kCubeModulus / 1000);
  std::printf("%8s %14s %12s %12s %7s\n", "FEM nu", "E_mss / E_fem", "misfit at E", "fitted",
              "time");
  for (const Real nu : {0.25, 0.3, 0.4, 0.45, 0.49}) {
    Scene fem = reference_cube.scene;
    fem.material.model = MaterialModel::linear;
    fem.material.poisson_ratio = nu;
    const MaterialParameters p = MaterialParameters::label_materials(fem, mesh);
    const ProbeData data = simulate_probe_data(fem, mesh, p, p.start(), cube.pushes);
    CalibrationOptions options;
    options.max_evaluations = 100;
    const CalibrationResult result =
        calibrate::calibrate(reference_cube.scene, mesh, data, options);
    std::printf("%8.2f %14.3f %12.3g %12.3g %6.2fs\n", nu, result.values[0].value / kCubeModulus,
                result.start_misfit, result.misfit, result.seconds);
  }
  return 0;
}
