#include "sim/calibrate/optimisers.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <stdexcept>

namespace incise::sim::calibrate {
namespace {

constexpr Real kInfinity = std::numeric_limits<Real>::infinity();

VecX clip(const VecX& z, const Problem& p) {
  return z.cwiseMax(p.lower).cwiseMin(p.upper);
}

// Counts evaluations against the budget and remembers the best point.
class Evaluator {
 public:
  Evaluator(const Problem& problem, const OptimiserSettings& settings, OptimiserResult& result)
      : problem_(problem), settings_(settings), result_(result) {
    result_.misfit = kInfinity;
  }

  // Also false once cancelled, so that a generation or a Jacobian stops within one simulation.
  bool can_evaluate(int n = 1) const {
    return result_.evaluations + n <= settings_.max_evaluations && !cancelled();
  }
  bool cancelled() const { return settings_.cancel != nullptr && settings_.cancel->load(); }

  // ||r(z)||^2, or infinity where z is not evaluable; r holds the residuals.
  Real misfit(const VecX& z, VecX& r) {
    ++result_.evaluations;
    bool ok = false;
    try {
      ok = problem_.residuals(z, r);
    } catch (...) {
      ok = false;
    }
    if (!ok || !r.allFinite()) return kInfinity;
    const Real m = r.squaredNorm();
    if (m < result_.misfit) {
      result_.misfit = m;
      result_.best = z;
    }
    return m;
  }
  Real misfit(const VecX& z) { return misfit(z, scratch_); }

  // The end of a generation or iteration: history and progress.
  void iteration_done() {
    ++result_.iterations;
    result_.history.push_back(result_.misfit);
    if (settings_.progress) {
      settings_.progress({result_.iterations, result_.evaluations, result_.misfit, result_.best});
    }
  }

 private:
  const Problem& problem_;
  const OptimiserSettings& settings_;
  OptimiserResult& result_;
  VecX scratch_;
};

void genetic_algorithm(const Problem& p, const OptimiserSettings& s, Evaluator& eval,
                       OptimiserResult& result) {
  const auto n = p.start.size();
  const int size = s.population > 0 ? std::max(s.population, 4) : 40;
  constexpr int kElite = 2;
  constexpr int kTournament = 3;
  constexpr Real kCrossover = 0.9;
  constexpr Real kBlend = 0.3;  // BLX-alpha
  const Real mutation_rate = std::max(Real(1) / static_cast<Real>(n), Real(0.1));
  std::mt19937_64 random(s.seed);
  std::normal_distribution<Real> normal;
  std::uniform_real_distribution<Real> uniform;

  std::vector<VecX> population;
  std::vector<Real> fitness;
  population.push_back(clip(p.start, p));
  while (static_cast<int>(population.size()) < size) {
    VecX z(n);
    for (Eigen::Index i = 0; i < n; ++i)
      z[i] = p.start[i] + s.initial_step * normal(random);
    population.push_back(clip(z, p));
  }
  fitness.push_back(result.start_misfit);  // population[0] is the start, evaluated already
  for (std::size_t k = 1; k < population.size() && eval.can_evaluate(); ++k) {
    fitness.push_back(eval.misfit(population[k]));
  }
  population.resize(fitness.size());
  eval.iteration_done();

  const auto tournament = [&]() -> const VecX& {
    std::size_t best = random() % population.size();
    for (int k = 1; k < kTournament; ++k) {
      const std::size_t other = random() % population.size();
      if (fitness[other] < fitness[best]) best = other;
    }
    return population[best];
  };
  std::vector<std::size_t> order;
  while (eval.can_evaluate() && !eval.cancelled() && population.size() >= 2) {
    order.resize(population.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(),
              [&](std::size_t a, std::size_t b) { return fitness[a] < fitness[b]; });
    std::vector<VecX> next;
    std::vector<Real> next_fitness;
    for (int e = 0; e < kElite && e < static_cast<int>(order.size()); ++e) {
      next.push_back(population[order[static_cast<std::size_t>(e)]]);
      next_fitness.push_back(fitness[order[static_cast<std::size_t>(e)]]);
    }
    // Mutation narrows as the budget is spent: explore first, then refine.
    const Real spent = static_cast<Real>(result.evaluations) / s.max_evaluations;
    const Real sigma = s.initial_step * (1 - 0.9 * spent);
    while (static_cast<int>(next.size()) < size && eval.can_evaluate()) {
      const VecX& a = tournament();
      const VecX& b = tournament();
      VecX child = a;
      if (uniform(random) < kCrossover) {
        for (Eigen::Index i = 0; i < n; ++i) {
          const Real lo = std::min(a[i], b[i]);
          const Real hi = std::max(a[i], b[i]);
          const Real d = hi - lo;
          child[i] = lo - kBlend * d + uniform(random) * (1 + 2 * kBlend) * d;
        }
      }
      for (Eigen::Index i = 0; i < n; ++i) {
        if (uniform(random) < mutation_rate) child[i] += sigma * normal(random);
      }
      child = clip(child, p);
      next_fitness.push_back(eval.misfit(child));
      next.push_back(std::move(child));
    }
    population = std::move(next);
    fitness = std::move(next_fitness);
    eval.iteration_done();
  }
  // The spread of the better half.
  order.resize(population.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return fitness[a] < fitness[b]; });
  const std::size_t half = std::max<std::size_t>(2, order.size() / 2);
  VecX mean = VecX::Zero(n);
  VecX square = VecX::Zero(n);
  std::size_t counted = 0;
  for (std::size_t k = 0; k < half && k < order.size(); ++k) {
    if (!std::isfinite(fitness[order[k]])) continue;
    mean += population[order[k]];
    square += population[order[k]].cwiseAbs2();
    ++counted;
  }
  if (counted > 0) {
    mean /= static_cast<Real>(counted);
    result.spread =
        (square / static_cast<Real>(counted) - mean.cwiseAbs2()).cwiseMax(0).cwiseSqrt();
  }
}

void cma_es(const Problem& p, const OptimiserSettings& s, Evaluator& eval,
            OptimiserResult& result) {
  const auto n = p.start.size();
  const Real nr = static_cast<Real>(n);
  const int lambda = s.population > 0 ? std::max(s.population, 4)
                                      : 4 + static_cast<int>(std::floor(3 * std::log(nr)));
  const int mu = lambda / 2;
  VecX w(mu);
  for (int i = 0; i < mu; ++i)
    w[i] = std::log((lambda + 1) / Real(2)) - std::log(Real(i + 1));
  w /= w.sum();
  const Real mu_eff = 1 / w.squaredNorm();
  const Real c_sigma = (mu_eff + 2) / (nr + mu_eff + 5);
  const Real d_sigma = 1 + 2 * std::max(Real(0), std::sqrt((mu_eff - 1) / (nr + 1)) - 1) + c_sigma;
  const Real c_c = (4 + mu_eff / nr) / (nr + 4 + 2 * mu_eff / nr);
  const Real c_1 = 2 / ((nr + 1.3) * (nr + 1.3) + mu_eff);
  const Real c_mu =
      std::min(1 - c_1, 2 * (mu_eff - 2 + 1 / mu_eff) / ((nr + 2) * (nr + 2) + mu_eff));
  const Real chi_n = std::sqrt(nr) * (1 - 1 / (4 * nr) + 1 / (21 * nr * nr));

  std::mt19937_64 random(s.seed);
  std::normal_distribution<Real> normal;
  VecX mean = clip(p.start, p);
  Real sigma = s.initial_step;
  Eigen::MatrixXd c = Eigen::MatrixXd::Identity(n, n);
  Eigen::MatrixXd b = Eigen::MatrixXd::Identity(n, n);
  VecX d = VecX::Ones(n);
  VecX p_sigma = VecX::Zero(n);
  VecX p_c = VecX::Zero(n);
  std::vector<VecX> y(static_cast<std::size_t>(lambda), VecX(n));
  std::vector<Real> f(static_cast<std::size_t>(lambda));
  std::vector<int> order(static_cast<std::size_t>(lambda));
  const Real width = (p.upper - p.lower).maxCoeff();
  int generation = 0;
  while (eval.can_evaluate(lambda) && !eval.cancelled()) {
    for (int k = 0; k < lambda; ++k) {
      if (eval.cancelled()) break;
      VecX z(n);
      for (Eigen::Index i = 0; i < n; ++i)
        z[i] = normal(random);
      const VecX x = clip(mean + sigma * (b * d.asDiagonal() * z), p);
      y[static_cast<std::size_t>(k)] = (x - mean) / sigma;  // the repaired step
      f[static_cast<std::size_t>(k)] = eval.misfit(x);
    }
    if (eval.cancelled()) break;  // a generation cut short updates nothing
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int c2) {
      return f[static_cast<std::size_t>(a)] < f[static_cast<std::size_t>(c2)];
    });
    VecX y_w = VecX::Zero(n);
    for (int i = 0; i < mu; ++i)
      y_w += w[i] * y[static_cast<std::size_t>(order[static_cast<std::size_t>(i)])];
    mean = clip(mean + sigma * y_w, p);
    const VecX c_inv_sqrt_y = b * d.cwiseInverse().asDiagonal() * (b.transpose() * y_w);
    p_sigma = (1 - c_sigma) * p_sigma + std::sqrt(c_sigma * (2 - c_sigma) * mu_eff) * c_inv_sqrt_y;
    ++generation;
    const Real h_sigma_test =
        p_sigma.norm() / std::sqrt(1 - std::pow(1 - c_sigma, 2.0 * generation)) / chi_n;
    const Real h_sigma = h_sigma_test < 1.4 + 2 / (nr + 1) ? 1 : 0;
    p_c = (1 - c_c) * p_c + h_sigma * std::sqrt(c_c * (2 - c_c) * mu_eff) * y_w;
    Eigen::MatrixXd rank_mu = Eigen::MatrixXd::Zero(n, n);
    for (int i = 0; i < mu; ++i) {
      const VecX& yi = y[static_cast<std::size_t>(order[static_cast<std::size_t>(i)])];
      rank_mu.noalias() += w[i] * yi * yi.transpose();
    }
    c = (1 - c_1 - c_mu) * c + c_1 * (p_c * p_c.transpose() + (1 - h_sigma) * c_c * (2 - c_c) * c) +
        c_mu * rank_mu;
    c = 0.5 * (c + c.transpose());
    sigma *= std::exp((c_sigma / d_sigma) * (p_sigma.norm() / chi_n - 1));
    sigma = std::min(sigma, width);
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(c);
    b = eigen.eigenvectors();
    d = eigen.eigenvalues().cwiseMax(1e-20).cwiseSqrt();
    eval.iteration_done();
    if (sigma * d.maxCoeff() < 1e-9 * width) {
      result.stopped = "converged";
      break;
    }
  }
  result.spread = sigma * c.diagonal().cwiseMax(0).cwiseSqrt();
}

void levenberg_marquardt(const Problem& p, const OptimiserSettings& s, Evaluator& eval,
                         OptimiserResult& result) {
  const auto n = p.start.size();
  VecX z = clip(p.start, p);
  VecX r;
  if (!eval.can_evaluate()) return;  // the start's residuals again: minimise kept only its misfit
  Real f = eval.misfit(z, r);
  if (!std::isfinite(f)) {
    result.stopped = "the start cannot be evaluated";
    return;
  }
  const auto m = r.size();
  Eigen::MatrixXd j(m, n);
  Eigen::MatrixXd a;
  VecX trial_r;
  Real lambda = 1e-3;
  while (!eval.cancelled()) {
    if (!eval.can_evaluate(static_cast<int>(n) + 1)) {
      result.stopped = "budget";
      break;
    }
    for (Eigen::Index k = 0; k < n; ++k) {
      if (eval.cancelled()) break;
      VecX zk = z;
      Real h = 1e-6 * std::max(Real(1), std::abs(z[k]));
      if (zk[k] + h > p.upper[k]) h = -h;
      zk[k] += h;
      const Real fk = eval.misfit(zk, trial_r);
      j.col(k) = std::isfinite(fk) ? VecX((trial_r - r) / h) : VecX::Zero(m);
    }
    if (eval.cancelled()) break;
    a.noalias() = j.transpose() * j;
    const VecX g = j.transpose() * r;
    const Real scale = std::max(a.diagonal().maxCoeff(), Real(1e-300));
    bool accepted = false;
    while (eval.can_evaluate() && !eval.cancelled()) {
      Eigen::MatrixXd damped = a;
      damped.diagonal() += lambda * (a.diagonal().array() + 1e-9 * scale).matrix();
      const VecX step = damped.ldlt().solve(-g);
      const VecX next = clip(z + step, p);
      const Real fn = eval.misfit(next, trial_r);
      if (fn < f) {
        const Real gain = (f - fn) / f;
        z = next;
        r = trial_r;
        f = fn;
        lambda = std::max(lambda / 3, Real(1e-12));
        accepted = true;
        if (gain < s.tolerance) result.stopped = "converged";
        break;
      }
      lambda *= 4;
      if (lambda > 1e12) break;
    }
    eval.iteration_done();
    if (!accepted) {
      if (result.stopped.empty()) {
        // No step lowered the misfit: converged, unless the budget or a cancel cut it short.
        result.stopped = eval.cancelled()       ? "cancelled"
                         : !eval.can_evaluate() ? "budget"
                                                : "converged";
      }
      break;
    }
    if (!result.stopped.empty()) break;
  }
  // Standard errors from the last Jacobian (at the accepted point or one step before).
  if (a.size() > 0) {
    const Real dof = m > n ? static_cast<Real>(m - n) : Real(1);
    Eigen::MatrixXd regular = a;
    regular.diagonal().array() += 1e-12 * std::max(a.diagonal().maxCoeff(), Real(1e-300));
    const Eigen::MatrixXd covariance =
        (f / dof) * regular.ldlt().solve(Eigen::MatrixXd::Identity(n, n));
    result.spread = covariance.diagonal().cwiseMax(0).cwiseSqrt();
  }
}

}  // namespace

std::optional<Method> method_named(std::string_view name) {
  if (name == "ga") return Method::ga;
  if (name == "cmaes") return Method::cmaes;
  if (name == "lm") return Method::lm;
  return std::nullopt;
}

std::string_view method_name(Method method) {
  switch (method) {
    case Method::ga:
      return "ga";
    case Method::cmaes:
      return "cmaes";
    case Method::lm:
      return "lm";
  }
  return "?";
}

OptimiserResult minimise(const Problem& problem, const OptimiserSettings& settings) {
  const auto n = problem.start.size();
  if (settings.max_evaluations < 1) throw std::invalid_argument("the budget is below 1");
  if (n == 0 || problem.lower.size() != n || problem.upper.size() != n) {
    throw std::invalid_argument("start, lower and upper differ in size (or are empty)");
  }
  if (!(problem.lower.array() < problem.upper.array()).all()) {
    throw std::invalid_argument("the box is empty on some coordinate");
  }
  if (!(settings.initial_step > 0) || !std::isfinite(settings.initial_step)) {
    throw std::invalid_argument("initial_step must be finite and > 0");
  }
  if (!problem.residuals) throw std::invalid_argument("the problem has no residuals");
  OptimiserResult result;
  result.spread = VecX::Zero(n);
  Evaluator eval(problem, settings, result);
  result.start_misfit = eval.misfit(clip(problem.start, problem));  // counts against the budget
  switch (settings.method) {
    case Method::ga:
      genetic_algorithm(problem, settings, eval, result);
      break;
    case Method::cmaes:
      cma_es(problem, settings, eval, result);
      break;
    case Method::lm:
      levenberg_marquardt(problem, settings, eval, result);
      break;
  }
  if (result.best.size() == 0) result.best = clip(problem.start, problem);
  if (result.stopped.empty()) {
    result.stopped = settings.cancel != nullptr && settings.cancel->load() ? "cancelled" : "budget";
  }
  return result;
}

}  // namespace incise::sim::calibrate
