#include "sim/solve/stable_time_step.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "sim/mesh/box_mesher.h"
#include "test_models.h"

namespace incise::sim {
namespace {

// Largest eigenvalue of M^-1 K by power iteration on the symmetric M^-1/2 K M^-1/2.
Real max_eigenvalue(const testing::LinearModel& model) {
  const VecX inv_sqrt_m =
      model.masses().cwiseSqrt().cwiseInverse().replicate(1, 3).transpose().reshaped();
  VecX y = VecX::LinSpaced(inv_sqrt_m.size(), 1, 2);
  Real lambda = 0;
  for (int it = 0; it < 3000; ++it) {
    const VecX z = inv_sqrt_m.cwiseProduct(model.stiffness() * inv_sqrt_m.cwiseProduct(y));
    lambda = y.dot(z) / y.dot(y);
    y = z.normalized();
  }
  return lambda;
}

TEST(StableTimeStep, PWaveSpeedClosedForms) {
  EXPECT_DOUBLE_EQ(p_wave_speed(4000, 0, 1000), 2.0);
  // nu = 1/4: (1 - nu) / ((1 + nu)(1 - 2 nu)) = 0.75 / 0.625 = 1.2
  EXPECT_NEAR(p_wave_speed(1e6, 0.25, 1000), std::sqrt(1.2e3), 1e-12);
  EXPECT_THROW(p_wave_speed(1e6, 0.5, 1000), std::invalid_argument);
  EXPECT_THROW(p_wave_speed(0, 0.3, 1000), std::invalid_argument);
  EXPECT_THROW(p_wave_speed(1e6, 0.3, -1), std::invalid_argument);
}

TEST(StableTimeStep, LengthsOfARegularTetAndABoxMesh) {
  Points p(4, 3);
  p << 1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1;  // regular, edge 2 sqrt(2)
  Tets t(1, 4);
  t << 0, 1, 2, 3;
  const ElementLengths regular = element_lengths(p, t);
  const Real a = 2 * std::sqrt(2.0);
  EXPECT_NEAR(regular.min_edge, a, 1e-12);
  EXPECT_NEAR(regular.min_altitude, a * std::sqrt(2.0 / 3.0), 1e-12);

  // Cells of side 0.1: the corner tets' altitude from the right-angled corner is 0.1 / sqrt(3).
  const TetMesh box = make_box_mesh(Vec3(0.4, 0.3, 0.2), Vec3i(4, 3, 2));
  const ElementLengths lengths = element_lengths(box.x, box.tets);
  EXPECT_NEAR(lengths.min_edge, 0.1, 1e-12);
  EXPECT_NEAR(lengths.min_altitude, 0.1 / std::sqrt(3.0), 1e-12);
}

TEST(StableTimeStep, FlatTetIsAPreciseError) {
  Points p(4, 3);
  p << 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0;
  Tets t(1, 4);
  t << 0, 1, 2, 3;
  try {
    element_lengths(p, t);
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("tet 0"), std::string::npos) << e.what();
  }
  EXPECT_THROW(element_lengths(p, Tets(0, 4)), std::invalid_argument);
}

TEST(StableTimeStep, EstimateIsBelowTheExactLimitOfLinearTets) {
  // The exact central-difference limit is 2 / omega_max with omega_max^2 the largest eigenvalue
  // of M^-1 K (lumped mass, constant-strain tets). The estimate must stay below it with the
  // default safety and not be needlessly small.
  const TetMesh mesh = make_box_mesh(Vec3(0.03, 0.02, 0.02), Vec3i(3, 2, 2));
  for (const Real nu : {0.0, 0.3, 0.45, 0.49}) {
    const testing::LinearModel model = testing::make_linear_tet_model(mesh, 5e3, nu, 1000);
    const Real exact = 2 / std::sqrt(max_eigenvalue(model));
    const Real estimate = stable_time_step(mesh, 5e3, nu, 1000);
    const Real ratio_at_safety_1 = stable_time_step(mesh, 5e3, nu, 1000, 1.0) / exact;
    RecordProperty("ratio_nu_" + std::to_string(nu), std::to_string(ratio_at_safety_1));
    std::printf("nu %.2f: exact dt %.4g s, l_min / c %.4g s, ratio %.3f\n", nu, exact,
                estimate / kExplicitSafety, ratio_at_safety_1);
    EXPECT_LT(estimate, exact) << "nu " << nu;
    EXPECT_GT(estimate, 0.45 * exact) << "nu " << nu;
    // l_min / c alone (safety 1) lands within 10% of the exact limit, slightly above it.
    EXPECT_GT(ratio_at_safety_1, 0.9) << "nu " << nu;
    EXPECT_LT(ratio_at_safety_1, 1.1) << "nu " << nu;
  }
}

TEST(StableTimeStep, FloorAndLengthAreInverse) {
  const Real dt_min = time_step_floor(2e-3, 4e3, 0.475, 1050);
  EXPECT_NEAR(length_floor(dt_min, 4e3, 0.475, 1050), 2e-3, 1e-15);
  EXPECT_NEAR(dt_min, kExplicitSafety * 2e-3 / p_wave_speed(4e3, 0.475, 1050), 1e-18);
  // A mesh whose shortest altitude is l_floor has exactly the floor as its stable step.
  const TetMesh mesh = make_box_mesh(Vec3(0.3, 0.3, 0.3), Vec3i(3, 3, 3));
  const Real l_min = element_lengths(mesh.x, mesh.tets).min_altitude;
  EXPECT_NEAR(stable_time_step(mesh, 4e3, 0.475, 1050), time_step_floor(l_min, 4e3, 0.475, 1050),
              1e-15);
  EXPECT_THROW(time_step_floor(0, 4e3, 0.475, 1050), std::invalid_argument);
  EXPECT_THROW(stable_time_step(mesh, 4e3, 0.475, 1050, 1.5), std::invalid_argument);
}

}  // namespace
}  // namespace incise::sim
