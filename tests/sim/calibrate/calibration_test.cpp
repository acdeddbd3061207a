// Calibration end to end (sim/calibrate/calibration.h): data from a reference model with known
// constants, the constants recovered from a wrong start, by each method; with noise; for the FEM
// models' E and nu; refusals of data and scenes it cannot use.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "sim/calibrate/calibration.h"
#include "sim/calibrate/cube_experiment.h"
#include "sim/io/scene_json.h"
#include "sim/mesh/box_mesher.h"

namespace incise::sim::calibrate {
namespace {

// Seed 004's cube with the reference modulus, and the same cube as a scene starting from
// start_modulus.
struct CubeData {
  explicit CubeData(int cells = 4, Real start_modulus = 2400)
      : cube(seed004_cube(start_modulus, cells)) {
    const CubeExperiment reference = seed004_cube(kCubeModulus, cells);
    const MaterialParameters p = MaterialParameters::label_materials(reference.scene, cube.mesh);
    data = simulate_probe_data(reference.scene, cube.mesh, p, p.start(), cube.pushes);
  }
  CubeExperiment cube;
  ProbeData data;
};

Real relative_error(Real value, Real reference) {
  return std::abs(value - reference) / reference;
}

TEST(Calibration, EachMethodRecoversTheCubesModulusFromNoiseFreeData) {
  const CubeData cube(2);  // a coarse cube: the methods are what is tested
  const struct {
    Method method;
    int budget;
    Real tolerance;
  } cases[] = {{Method::lm, 100, 1e-8}, {Method::cmaes, 600, 1e-5}, {Method::ga, 1500, 1e-2}};
  for (const auto& c : cases) {
    CalibrationOptions options;
    options.method = c.method;
    options.max_evaluations = c.budget;
    const CalibrationResult result = calibrate(cube.cube.scene, cube.cube.mesh, cube.data, options);
    ASSERT_EQ(result.values.size(), 1u);  // E of label 0; the mass-spring model has no nu
    EXPECT_EQ(result.values[0].name, "E[0]");
    EXPECT_DOUBLE_EQ(result.values[0].start, 2400);
    EXPECT_LT(relative_error(result.values[0].value, kCubeModulus), c.tolerance)
        << method_name(c.method) << ": " << result.values[0].value;
    EXPECT_LE(result.search.evaluations, c.budget);
    EXPECT_LT(result.misfit, 1e-3 * result.start_misfit);
    EXPECT_EQ(result.calibrated.material.youngs_modulus, result.values[0].value);
    // The curves: five pushes, the fitted one on the measured one, the start's off it.
    ASSERT_EQ(result.fits.size(), 5u);
    for (const ContactFit& fit : result.fits) {
      ASSERT_EQ(fit.measured.size(), static_cast<std::size_t>(kCubeSamples));
      EXPECT_NEAR(fit.force.back(), kCubeForce, 1e-15);
      EXPECT_GT(fit.measured.back(), 0);  // pushed in, along the push
      EXPECT_NEAR(fit.fitted.back(), fit.measured.back(), 0.05 * fit.measured.back());
      EXPECT_GT(fit.start.back(), 1.3 * fit.measured.back());  // 2.4 kPa gives way 1.5 times more
    }
  }
}

TEST(Calibration, NoiseDegradesTheModulusGracefully) {
  const CubeData cube;
  Real previous = 0;
  for (const Real noise : {0.01, 0.05, 0.2}) {
    CalibrationOptions options;
    options.max_evaluations = 100;
    const CalibrationResult result = calibrate(cube.cube.scene, cube.cube.mesh,
                                               with_position_noise(cube.data, noise, 11), options);
    const Real error = relative_error(result.values[0].value, kCubeModulus);
    // Thousands of samples average the noise out: far below the noise itself.
    EXPECT_LT(error, 0.1 * noise) << "noise " << noise;
    EXPECT_GT(result.values[0].spread, 0);
    // The standard error covers the actual error (within three of it).
    EXPECT_LT(std::abs(result.values[0].value - kCubeModulus), 3 * result.values[0].spread + 1e-9)
        << "noise " << noise;
    EXPECT_GT(result.values[0].spread, previous);  // more noise, a wider spread
    previous = result.values[0].spread;
  }
}

TEST(Calibration, NodeModuliOfAHomogeneousCubeComeBackFromTheFivePushes) {
  const CubeData cube;
  CalibrationOptions options;
  options.parameters = ParameterKind::node_moduli;
  options.max_evaluations = 600;
  const CalibrationResult result = calibrate(cube.cube.scene, cube.cube.mesh, cube.data, options);
  ASSERT_EQ(result.values.size(), static_cast<std::size_t>(cube.cube.mesh.num_nodes()));
  Real largest = 0;
  for (const CalibratedValue& v : result.values) {
    largest = std::max(largest, relative_error(v.value, kCubeModulus));
  }
  EXPECT_LT(largest, 0.0949) << "seed 004's largest error was 9.49 %";
  EXPECT_LT(result.misfit, 1e-4 * result.start_misfit);
  // What a scene file can hold: the label's mean modulus.
  EXPECT_LT(relative_error(result.calibrated.material.youngs_modulus, kCubeModulus), 0.01);
}

// A linear FEM cube with E = 5 kPa, nu = 0.4, from a start of 3 kPa and 0.3.
TEST(Calibration, RecoversTheYoungsModulusAndPoissonsRatioOfAnFemBody) {
  CubeExperiment cube = seed004_cube(3000);
  cube.scene.material.model = MaterialModel::linear;
  Scene reference = cube.scene;
  reference.material.youngs_modulus = 5000;
  reference.material.poisson_ratio = 0.4;
  const MaterialParameters p = MaterialParameters::label_materials(reference, cube.mesh);
  ASSERT_EQ(p.size(), 2);
  EXPECT_EQ(p.names()[1], "nu[0]");
  const ProbeData data = simulate_probe_data(reference, cube.mesh, p, p.start(), cube.pushes);
  CalibrationOptions options;
  options.max_evaluations = 300;
  const CalibrationResult result = calibrate(cube.scene, cube.mesh, data, options);
  EXPECT_LT(relative_error(result.values[0].value, 5000), 1e-4) << result.values[0].value;
  EXPECT_NEAR(result.values[1].value, 0.4, 1e-4);
  EXPECT_EQ(result.calibrated.material.poisson_ratio, result.values[1].value);
}

// A spring lattice models a solid of Poisson's ratio 1/4: pushed like a linear FEM cube of
// nu = 0.25 it needs the FEM's own E, pushed like a nearly incompressible one (nu = 0.45, the
// tissues' value) a higher E, which calibration finds, matching the FEM body better.
TEST(Calibration, TheMassSpringCubeCalibratedToFemCubesFollowsTheirPoissonsRatio) {
  const CubeExperiment mss = seed004_cube(kCubeModulus);
  const auto calibrated = [&](Real nu) {
    Scene fem = mss.scene;
    fem.material.model = MaterialModel::linear;
    fem.material.poisson_ratio = nu;
    const MaterialParameters p = MaterialParameters::label_materials(fem, mss.mesh);
    const ProbeData data = simulate_probe_data(fem, mss.mesh, p, p.start(), mss.pushes);
    CalibrationOptions options;
    options.max_evaluations = 60;
    return calibrate(mss.scene, mss.mesh, data, options);
  };
  const CalibrationResult cauchy = calibrated(0.25);
  EXPECT_LT(relative_error(cauchy.values[0].value, kCubeModulus), 0.02);
  const CalibrationResult tissue = calibrated(0.45);
  EXPECT_GT(tissue.values[0].value, 1.05 * kCubeModulus);
  EXPECT_LT(tissue.values[0].value, 1.3 * kCubeModulus);
  EXPECT_LT(tissue.misfit, 0.5 * tissue.start_misfit);
}

TEST(Calibration, RefusesWhatItCannotUse) {
  const CubeData cube;
  const auto refusal = [&](const Scene& scene, const ProbeData& data,
                           ParameterKind kind = ParameterKind::label_materials) -> std::string {
    CalibrationOptions options;
    options.parameters = kind;
    options.max_evaluations = 5;
    try {
      calibrate(scene, cube.cube.mesh, data, options);
    } catch (const CalibrationError& e) {
      return e.what();
    }
    return "";
  };
  Scene some_axes = cube.cube.scene;
  some_axes.constraints[0].axes = {false, false, true};
  EXPECT_NE(refusal(some_axes, cube.data).find("holds only some axes"), std::string::npos);
  Scene all_fixed = cube.cube.scene;
  all_fixed.constraints[0].where.box = Box3(Vec3::Zero(), Vec3::Constant(kCubeEdge));
  EXPECT_NE(refusal(all_fixed, cube.data).find("every node fixed"), std::string::npos);
  ProbeData still = cube.cube.pushes;  // positions never change
  EXPECT_NE(refusal(cube.cube.scene, still).find("never moves"), std::string::npos);
  ProbeData on_the_floor = cube.data;  // a probe on the fixed bottom: nearest free node too far
  for (auto& s : on_the_floor.contacts[0].samples)
    s.position = Vec3(0.005, 0.005, -0.004);
  EXPECT_NE(refusal(cube.cube.scene, on_the_floor).find("no contact"), std::string::npos);
  Scene fem = cube.cube.scene;
  fem.material.model = MaterialModel::corotational;
  EXPECT_NE(refusal(fem, cube.data, ParameterKind::node_moduli).find("mass-spring"),
            std::string::npos);
}

// The demo data next to the demo scene is what the reference cube gives, not numbers made up.
TEST(Calibration, TheShippedCubeDataIsTheReferenceCubes) {
  std::ifstream file(INCISE_SCENES_DIR "/calibration/cube_pushes.csv");
  std::ostringstream text;
  text << file.rdbuf();
  const ProbeData shipped = parse_probe_csv(text.str());
  const CubeData cube;
  ASSERT_EQ(shipped.contacts.size(), cube.data.contacts.size());
  for (std::size_t c = 0; c < shipped.contacts.size(); ++c) {
    ASSERT_EQ(shipped.contacts[c].samples.size(), cube.data.contacts[c].samples.size());
    for (std::size_t k = 0; k < shipped.contacts[c].samples.size(); ++k) {
      EXPECT_LT(
          (shipped.contacts[c].samples[k].position - cube.data.contacts[c].samples[k].position)
              .norm(),
          1e-12);
    }
  }
  const Scene scene = read_scene_file(INCISE_SCENES_DIR "/calibration/cube.json");
  EXPECT_EQ(scene.material.youngs_modulus, 2400);
  EXPECT_EQ(scene.mesh.box.cells, Vec3i::Constant(4));
}

}  // namespace
}  // namespace incise::sim::calibrate
