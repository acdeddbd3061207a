#include "sim/io/result_json.h"

#include <gtest/gtest.h>

#include <limits>

namespace incise::sim {
namespace {

TEST(ResultToJson, WritesTheContractFields) {
  RunResult result;
  result.rest.resize(2, 3);
  result.rest << 0, 0, 0, 0.1, 0.2, 0.3;
  result.displacement.resize(2, 3);
  result.displacement << 0, 0, 0, 0.001, -0.002, 0.003;
  result.num_tets = 7;
  result.steps = 42;
  result.ms_per_step = 0.25;
  result.max_speed = 1.5e-3;
  const nlohmann::json json = result_to_json(result);
  EXPECT_EQ(json.size(), 10u);
  EXPECT_EQ(json.at("nodes"), 2);
  EXPECT_EQ(json.at("tets"), 7);
  EXPECT_EQ(json.at("rest"), nlohmann::json::parse("[[0.0, 0.0, 0.0], [0.1, 0.2, 0.3]]"));
  EXPECT_EQ(json.at("displacement")[1], nlohmann::json::parse("[0.001, -0.002, 0.003]"));
  EXPECT_EQ(json.at("steps"), 42);
  EXPECT_EQ(json.at("ms_per_step"), 0.25);
  EXPECT_EQ(json.at("max_speed"), 1.5e-3);
  EXPECT_EQ(json.at("finite"), true);
  EXPECT_EQ(json.at("status"), "completed");
  EXPECT_EQ(json.at("solver"), nlohmann::json::parse(R"({"converged": true, "iterations": 0,
                                                         "relative_residual": 0.0,
                                                         "inverted_elements": 0})"));
}

TEST(ResultToJson, NonFiniteNumbersBecomeNull) {
  RunResult result;
  result.rest = Points::Zero(1, 3);
  result.displacement.resize(1, 3);
  result.displacement << std::numeric_limits<Real>::quiet_NaN(), 1, 0;
  result.max_speed = std::numeric_limits<Real>::infinity();
  result.finite = false;
  const nlohmann::json json = result_to_json(result);
  EXPECT_TRUE(json.at("displacement")[0][0].is_null());
  EXPECT_EQ(json.at("displacement")[0][1], 1.0);
  EXPECT_TRUE(json.at("max_speed").is_null());
  EXPECT_EQ(json.at("finite"), false);
  // And the document stays valid JSON.
  EXPECT_NO_THROW(nlohmann::json::parse(json.dump()));
}

}  // namespace
}  // namespace incise::sim
