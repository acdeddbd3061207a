#include "sim/io/result_json.h"

#include <cmath>

namespace incise::sim {
namespace {

using nlohmann::json;

json number(Real value) {
  return std::isfinite(value) ? json(value) : json(nullptr);
}

json rows(const Points& points) {
  json array = json::array();
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    array.push_back({number(points(i, 0)), number(points(i, 1)), number(points(i, 2))});
  }
  return array;
}

}  // namespace

json result_to_json(const RunResult& result) {
  return {{"nodes", result.rest.rows()},
          {"tets", result.num_tets},
          {"rest", rows(result.rest)},
          {"displacement", rows(result.displacement)},
          {"steps", result.steps},
          {"ms_per_step", number(result.ms_per_step)},
          {"max_speed", number(result.max_speed)},
          {"finite", result.finite},
          {"status", result.status},
          {"solver",
           {{"converged", result.converged},
            {"iterations", result.iterations},
            {"relative_residual", number(result.relative_residual)},
            {"inverted_elements", result.inverted_elements}}}};
}

}  // namespace incise::sim
