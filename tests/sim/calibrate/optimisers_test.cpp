// The searches of calibration (sim/calibrate/optimisers.h) on problems whose answers are known:
// each method finds Rosenbrock's minimum; the misfit never rises; the budget, the box and the
// cancel flag hold; ga and cmaes are deterministic for a seed; points that cannot be evaluated
// neither stop a search nor escape it; and lm's spread is the textbook standard error of a
// linear fit.
#include "sim/calibrate/optimisers.h"

#include <gtest/gtest.h>
#include <Eigen/LU>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <initializer_list>
#include <stdexcept>
#include <string>
#include <vector>

namespace incise::sim::calibrate {
namespace {

constexpr Method kMethods[] = {Method::ga, Method::cmaes, Method::lm};

VecX vec(std::initializer_list<Real> values) {
  VecX v(static_cast<Eigen::Index>(values.size()));
  Eigen::Index i = 0;
  for (const Real x : values)
    v[i++] = x;
  return v;
}

std::vector<Real> values(const VecX& v) {
  return {v.data(), v.data() + v.size()};
}

// Rosenbrock's function 100 (z1 - z0^2)^2 + (1 - z0)^2 as least squares, from its classic start
// (-1.2, 1) in the box [-5, 5]^2: the minimum 0 is at (1, 1), at the end of a long curved valley.
bool rosenbrock_residuals(const VecX& z, VecX& r) {
  r = vec({10 * (z[1] - z[0] * z[0]), 1 - z[0]});
  return true;
}

Problem rosenbrock() {
  Problem p;
  p.start = vec({-1.2, 1});
  p.lower = vec({-5, -5});
  p.upper = vec({5, 5});
  p.residuals = rosenbrock_residuals;
  return p;
}

Real rosenbrock_misfit(const VecX& z) {
  VecX r;
  rosenbrock_residuals(z, r);
  return r.squaredNorm();
}

// Each method with a budget that reaches Rosenbrock's minimum (lm needs about 100 evaluations,
// cmaes about 1500), and how close it gets.
struct Search {
  OptimiserSettings settings;
  Real misfit_below = 0;  // the misfit it reaches
  Real distance = 0;      // from (1, 1)
};

Search search(Method method) {
  Search s;
  s.settings.method = method;
  switch (method) {
    case Method::lm:
      s.settings.max_evaluations = 500;
      s.misfit_below = 1e-12;
      s.distance = 1e-5;
      break;
    case Method::cmaes:
      s.settings.max_evaluations = 3000;
      s.misfit_below = 1e-12;
      s.distance = 1e-5;
      break;
    case Method::ga:
      // ga's stall test (30 generations without a relative gain above the tolerance) stops it in
      // Rosenbrock's valley long before its mutation has narrowed, at misfits up to 1e-2 for some
      // seeds; a negative tolerance turns the test off, and the whole budget then ends below 1e-5
      // for every seed tried (200, in a Python port of the search).
      s.settings.max_evaluations = 20000;
      s.settings.population = 60;
      s.settings.tolerance = -1;
      s.misfit_below = 1e-4;
      s.distance = 0.05;
      break;
  }
  return s;
}

bool inside(const VecX& z, const Problem& p) {
  return z.size() == p.lower.size() && (z.array() >= p.lower.array()).all() &&
         (z.array() <= p.upper.array()).all();
}

TEST(MethodNamed, NamesEachMethod) {
  for (const Method method : kMethods)
    EXPECT_EQ(method_named(method_name(method)), method);
  EXPECT_EQ(method_name(Method::ga), "ga");
  EXPECT_EQ(method_name(Method::cmaes), "cmaes");
  EXPECT_EQ(method_name(Method::lm), "lm");
  for (const char* unknown : {"", "GA", "lm ", "cma-es", "nelder-mead"})
    EXPECT_FALSE(method_named(unknown).has_value()) << unknown;
}

TEST(Minimise, FindsRosenbrocksMinimum) {
  for (const Method method : kMethods) {
    SCOPED_TRACE(std::string(method_name(method)));
    const Search s = search(method);
    const OptimiserResult result = minimise(rosenbrock(), s.settings);
    EXPECT_LT(result.misfit, s.misfit_below) << "stopped: " << result.stopped;
    ASSERT_EQ(result.best.size(), 2);
    EXPECT_LT((result.best - vec({1, 1})).norm(), s.distance)
        << "best (" << result.best[0] << ", " << result.best[1] << ")";
    EXPECT_TRUE(inside(result.best, rosenbrock()));
    EXPECT_DOUBLE_EQ(result.start_misfit, rosenbrock_misfit(vec({-1.2, 1})));
  }
}

TEST(Minimise, TheMisfitNeverRises) {
  for (const Method method : kMethods) {
    SCOPED_TRACE(std::string(method_name(method)));
    const OptimiserResult result = minimise(rosenbrock(), search(method).settings);
    ASSERT_FALSE(result.history.empty());
    EXPECT_EQ(result.history.size(), static_cast<std::size_t>(result.iterations));
    for (std::size_t k = 1; k < result.history.size(); ++k)
      EXPECT_LE(result.history[k], result.history[k - 1]) << "iteration " << k + 1;
    EXPECT_EQ(result.history.back(), result.misfit);
    EXPECT_LE(result.misfit, result.start_misfit);
    // The misfit reported is the best point's.
    EXPECT_DOUBLE_EQ(rosenbrock_misfit(result.best), result.misfit);
  }
}

TEST(Minimise, NeverEvaluatesMoreThanTheBudget) {
  for (const Method method : kMethods) {
    for (const int budget : {1, 2, 5, 17, 100}) {
      SCOPED_TRACE(std::string(method_name(method)) + ", budget " + std::to_string(budget));
      int calls = 0;
      Problem p = rosenbrock();
      p.residuals = [&calls](const VecX& z, VecX& r) {
        ++calls;
        return rosenbrock_residuals(z, r);
      };
      OptimiserSettings settings;
      settings.method = method;
      settings.max_evaluations = budget;
      const OptimiserResult result = minimise(p, settings);
      EXPECT_EQ(result.evaluations, calls);
      EXPECT_LE(calls, budget);
      EXPECT_GE(calls, 1);  // the start, at least
      EXPECT_EQ(result.history.size(), static_cast<std::size_t>(result.iterations));
      EXPECT_LE(result.misfit, result.start_misfit);
      EXPECT_TRUE(inside(result.best, p));
      EXPECT_FALSE(result.stopped.empty());
    }
  }
}

TEST(Minimise, RefusesABadBudgetOrBox) {
  for (const Method method : kMethods) {
    SCOPED_TRACE(std::string(method_name(method)));
    OptimiserSettings settings;
    settings.method = method;
    for (const int budget : {0, -1}) {
      settings.max_evaluations = budget;
      EXPECT_THROW(minimise(rosenbrock(), settings), std::invalid_argument) << budget;
    }
    settings.max_evaluations = 100;
    Problem p = rosenbrock();
    p.lower = vec({-5});
    EXPECT_THROW(minimise(p, settings), std::invalid_argument) << "lower of size 1";
    p = rosenbrock();
    p.upper = vec({5, 5, 5});
    EXPECT_THROW(minimise(p, settings), std::invalid_argument) << "upper of size 3";
    p = rosenbrock();
    p.start = vec({0});
    EXPECT_THROW(minimise(p, settings), std::invalid_argument) << "start of size 1";
    p.start = p.lower = p.upper = VecX();
    EXPECT_THROW(minimise(p, settings), std::invalid_argument) << "empty";
    p = rosenbrock();
    p.upper[1] = p.lower[1];
    EXPECT_THROW(minimise(p, settings), std::invalid_argument) << "lower == upper";
    p = rosenbrock();
    p.lower[0] = 6;
    EXPECT_THROW(minimise(p, settings), std::invalid_argument) << "lower > upper";
  }
}

TEST(Minimise, GaAndCmaesAreDeterministicForASeed) {
  for (const Method method : {Method::ga, Method::cmaes}) {
    SCOPED_TRACE(std::string(method_name(method)));
    OptimiserSettings settings;
    settings.method = method;
    settings.max_evaluations = 2000;
    settings.seed = 7;
    const OptimiserResult a = minimise(rosenbrock(), settings);
    const OptimiserResult b = minimise(rosenbrock(), settings);
    EXPECT_EQ(values(a.best), values(b.best));
    EXPECT_EQ(a.misfit, b.misfit);
    EXPECT_EQ(a.history, b.history);
    EXPECT_EQ(values(a.spread), values(b.spread));
    EXPECT_EQ(a.evaluations, b.evaluations);
    EXPECT_EQ(a.stopped, b.stopped);
    settings.seed = 8;
    const OptimiserResult c = minimise(rosenbrock(), settings);
    EXPECT_NE(a.history, c.history) << "seeds 7 and 8 searched alike";
  }
}

TEST(Minimise, StaysInTheBox) {
  // r = z - 10 in the box [0, 1]: the minimum is beyond the upper bound, so each method ends on
  // it exactly, with misfit 81, and never evaluates outside the box on the way.
  for (const Method method : kMethods) {
    SCOPED_TRACE(std::string(method_name(method)));
    Problem p;
    p.start = vec({0.5});
    p.lower = vec({0});
    p.upper = vec({1});
    bool outside = false;
    p.residuals = [&](const VecX& z, VecX& r) {
      outside = outside || !inside(z, p);
      r = vec({z[0] - 10});
      return true;
    };
    OptimiserSettings settings;
    settings.method = method;
    settings.max_evaluations = 2000;
    const OptimiserResult result = minimise(p, settings);
    ASSERT_EQ(result.best.size(), 1);
    EXPECT_EQ(result.best[0], 1.0);
    EXPECT_EQ(result.misfit, 81.0);
    EXPECT_FALSE(outside);
  }
  // The same in two dimensions, and for Rosenbrock: the best stays inside.
  for (const Method method : kMethods) {
    SCOPED_TRACE(std::string(method_name(method)) + ", Rosenbrock in [-2, 0.5] x [0.5, 3]");
    Problem p = rosenbrock();
    p.lower = vec({-2, 0.5});
    p.upper = vec({0.5, 3});
    bool outside = false;
    p.residuals = [&](const VecX& z, VecX& r) {
      outside = outside || !inside(z, p);
      return rosenbrock_residuals(z, r);
    };
    OptimiserSettings settings = search(method).settings;
    settings.max_evaluations = std::min(settings.max_evaluations, 3000);
    const OptimiserResult result = minimise(p, settings);
    EXPECT_TRUE(inside(result.best, p));
    EXPECT_FALSE(outside);
    EXPECT_LE(result.misfit, result.start_misfit);
  }
}

TEST(Minimise, StopsWhenCancelled) {
  for (const Method method : kMethods) {
    SCOPED_TRACE(std::string(method_name(method)));
    std::atomic<bool> cancel = false;
    OptimiserSettings settings = search(method).settings;
    settings.cancel = &cancel;
    settings.progress = [&](const Progress& progress) {
      if (progress.iteration == 3) cancel = true;
    };
    const OptimiserResult result = minimise(rosenbrock(), settings);
    EXPECT_EQ(result.stopped, "cancelled");
    // Each method looks at the flag before every generation or iteration, so the third is the
    // last (the header promises only "soon": no more than one more).
    EXPECT_GE(result.iterations, 3);
    EXPECT_LE(result.iterations, 4);
    EXPECT_LT(result.evaluations, settings.max_evaluations);
  }
  // Already set: at most the first generation (ga evaluates its initial population whole).
  for (const Method method : kMethods) {
    SCOPED_TRACE(std::string(method_name(method)) + ", cancelled from the start");
    const std::atomic<bool> cancel = true;
    OptimiserSettings settings = search(method).settings;
    settings.cancel = &cancel;
    const OptimiserResult result = minimise(rosenbrock(), settings);
    EXPECT_EQ(result.stopped, "cancelled");
    EXPECT_LE(result.iterations, 1);
    EXPECT_LE(result.misfit, result.start_misfit);
  }
}

TEST(Minimise, ReportsProgressOncePerIteration) {
  for (const Method method : kMethods) {
    SCOPED_TRACE(std::string(method_name(method)));
    std::vector<Progress> reports;
    OptimiserSettings settings = search(method).settings;
    settings.progress = [&](const Progress& progress) { reports.push_back(progress); };
    const OptimiserResult result = minimise(rosenbrock(), settings);
    ASSERT_EQ(reports.size(), static_cast<std::size_t>(result.iterations));
    ASSERT_EQ(reports.size(), result.history.size());
    for (std::size_t k = 0; k < reports.size(); ++k) {
      SCOPED_TRACE("report " + std::to_string(k));
      EXPECT_EQ(reports[k].iteration, static_cast<int>(k) + 1);
      EXPECT_EQ(reports[k].misfit, result.history[k]);
      EXPECT_DOUBLE_EQ(rosenbrock_misfit(reports[k].best), reports[k].misfit);
      EXPECT_LE(reports[k].evaluations, result.evaluations);
      if (k > 0) {
        EXPECT_LE(reports[k].misfit, reports[k - 1].misfit);
        EXPECT_GT(reports[k].evaluations, reports[k - 1].evaluations);
      }
    }
  }
}

// Rosenbrock, except that z0 above 2 cannot be evaluated and z0 below -4 throws (or the other way
// round, swapped), counting how often each happened.
struct Unreliable {
  bool swapped = false;
  int refused = 0;
  int thrown = 0;
};

Problem unreliable_rosenbrock(Unreliable& u, const VecX& start) {
  Problem p = rosenbrock();
  p.start = start;
  p.residuals = [&u](const VecX& z, VecX& r) {
    if (z[0] > 2 || z[0] < -4) {
      if ((z[0] > 2) != u.swapped) {
        ++u.refused;
        return false;
      }
      ++u.thrown;
      throw std::domain_error("outside the model's range");
    }
    return rosenbrock_residuals(z, r);
  };
  return p;
}

void expect_a_finite_result(const OptimiserResult& result, const Problem& p) {
  EXPECT_TRUE(std::isfinite(result.misfit)) << "stopped: " << result.stopped;
  EXPECT_LT(result.misfit, result.start_misfit);
  EXPECT_TRUE(result.best.allFinite());
  EXPECT_TRUE(inside(result.best, p));
  EXPECT_GE(result.best[0], -4);
  EXPECT_LE(result.best[0], 2);
  for (const Real h : result.history)
    EXPECT_FALSE(std::isnan(h));
}

TEST(Minimise, PointsThatCannotBeEvaluatedNeitherStopNorEscape) {
  // ga and cmaes spread widely from the start (a seed's first generations reach both regions).
  for (const Method method : {Method::ga, Method::cmaes}) {
    SCOPED_TRACE(std::string(method_name(method)));
    Unreliable u;
    const Problem p = unreliable_rosenbrock(u, vec({-1.2, 1}));
    OptimiserSettings settings;
    settings.method = method;
    settings.max_evaluations = method == Method::ga ? 4000 : 3000;
    settings.initial_step = method == Method::ga ? 3 : 4;
    settings.population = method == Method::ga ? 0 : 30;
    OptimiserResult result;
    EXPECT_NO_THROW(result = minimise(p, settings));
    EXPECT_GT(u.refused, 0) << "the test did not reach z0 > 2";
    EXPECT_GT(u.thrown, 0) << "the test did not reach z0 < -4";
    expect_a_finite_result(result, p);
  }
  // lm steps to z0 = 1 (the residual 1 - z0 is linear), so it meets the regions only in its
  // forward differences: from just below 2, whose step crosses it, once refused and once thrown.
  for (const bool swapped : {false, true}) {
    SCOPED_TRACE(swapped ? "lm, throws above 2" : "lm, refused above 2");
    Unreliable u;
    u.swapped = swapped;
    const Problem p = unreliable_rosenbrock(u, vec({1.9999995, 3.9}));
    OptimiserSettings settings;
    settings.method = Method::lm;
    settings.max_evaluations = 500;
    OptimiserResult result;
    EXPECT_NO_THROW(result = minimise(p, settings));
    EXPECT_GT(swapped ? u.thrown : u.refused, 0) << "the test did not reach z0 > 2";
    expect_a_finite_result(result, p);
  }
}

TEST(Minimise, LmSpreadIsTheStandardErrorOfALinearFit) {
  // y = 1.5 x - 0.7 plus deterministic noise of amplitude 0.05 at x = 0, 0.25, ..., 4.75, fitted
  // as r_i = a x_i + b - y_i: lm must land on the least-squares solution and report its standard
  // errors sqrt(s^2 ((X^T X)^-1)_jj), s^2 = RSS / (m - 2).
  constexpr int m = 20;
  Eigen::MatrixXd x(m, 2);
  VecX y(m);
  for (int i = 0; i < m; ++i) {
    x(i, 0) = 0.25 * i;
    x(i, 1) = 1;
    y[i] = 1.5 * x(i, 0) - 0.7 + 0.05 * std::sin(1.3 * i * i + 0.4);
  }
  const Eigen::Matrix2d xtx_inverse = (x.transpose() * x).inverse();
  const Eigen::Vector2d exact = xtx_inverse * (x.transpose() * y);
  const Real rss = (x * exact - y).squaredNorm();
  const Eigen::Matrix2d covariance = rss / (m - 2) * xtx_inverse;

  Problem p;
  p.start = vec({0, 0});
  p.lower = vec({-10, -10});
  p.upper = vec({10, 10});
  p.residuals = [&](const VecX& z, VecX& r) {
    r = x * z - y;
    return true;
  };
  OptimiserSettings settings;
  settings.method = Method::lm;
  settings.max_evaluations = 500;
  const OptimiserResult result = minimise(p, settings);
  ASSERT_EQ(result.best.size(), 2);
  ASSERT_EQ(result.spread.size(), 2);
  for (int j = 0; j < 2; ++j) {
    SCOPED_TRACE(j == 0 ? "slope" : "intercept");
    EXPECT_NEAR(result.best[j], exact[j], 1e-8);
    const Real standard_error = std::sqrt(covariance(j, j));
    EXPECT_NEAR(result.spread[j], standard_error, 1e-4 * standard_error);
  }
  EXPECT_NEAR(result.misfit, rss, 1e-12 * rss);
}

}  // namespace
}  // namespace incise::sim::calibrate
