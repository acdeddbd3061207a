#include "sim/models/corotational_batch.h"

#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "sim/models/lanes.h"
#include "sim/models/tet_fem_model.h"

namespace incise::sim {

namespace {

using namespace lanes;
static_assert(CorotationalBatch::kLanes == kLaneWidth);

// A 3x3 matrix of lanes, m[i][j] row i column j.
struct M3 {
  Lanes m[3][3];
};

INCISE_LANES M3 times(const M3& a, const M3& b) {
  M3 c;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      c.m[i][j] = a.m[i][0] * b.m[0][j] + a.m[i][1] * b.m[1][j] + a.m[i][2] * b.m[2][j];
  return c;
}
// a^T b
INCISE_LANES M3 transpose_times(const M3& a, const M3& b) {
  M3 c;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      c.m[i][j] = a.m[0][i] * b.m[0][j] + a.m[1][i] * b.m[1][j] + a.m[2][i] * b.m[2][j];
  return c;
}
// a b^T
INCISE_LANES M3 times_transpose(const M3& a, const M3& b) {
  M3 c;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      c.m[i][j] = a.m[i][0] * b.m[j][0] + a.m[i][1] * b.m[j][1] + a.m[i][2] * b.m[j][2];
  return c;
}
INCISE_LANES Lanes determinant(const M3& a) {
  return a.m[0][0] * (a.m[1][1] * a.m[2][2] - a.m[1][2] * a.m[2][1]) -
         a.m[0][1] * (a.m[1][0] * a.m[2][2] - a.m[1][2] * a.m[2][0]) +
         a.m[0][2] * (a.m[1][0] * a.m[2][1] - a.m[1][1] * a.m[2][0]);
}
// C(sym(e) - shift I) = 2 mu (sym(e) - shift I) + lambda tr(sym(e) - shift I) I.
INCISE_LANES M3 linear_stress_of(const M3& e, Real shift, Lanes mu, Lanes lambda) {
  const Lanes trace = e.m[0][0] + e.m[1][1] + e.m[2][2] - 3 * shift;
  M3 s;
  for (int i = 0; i < 3; ++i) {
    for (int j = i; j < 3; ++j) {
      const Lanes strain = i == j ? e.m[i][i] - shift : Real(0.5) * (e.m[i][j] + e.m[j][i]);
      s.m[i][j] = s.m[j][i] = 2 * mu * strain;
    }
    s.m[i][i] += lambda * trace;
  }
  return s;
}

// |q|^2 times the rotation of the quaternion q (w, x, y, z), whatever its length.
INCISE_LANES M3 homogeneous_rotation_of(Lanes w, Lanes x, Lanes y, Lanes z) {
  const Lanes ww = w * w, xx = x * x, yy = y * y, zz = z * z;
  M3 r;
  r.m[0][0] = ww + xx - yy - zz;
  r.m[0][1] = 2 * (x * y - w * z);
  r.m[0][2] = 2 * (x * z + w * y);
  r.m[1][0] = 2 * (x * y + w * z);
  r.m[1][1] = ww - xx + yy - zz;
  r.m[1][2] = 2 * (y * z - w * x);
  r.m[2][0] = 2 * (x * z - w * y);
  r.m[2][1] = 2 * (y * z + w * x);
  r.m[2][2] = ww - xx - yy + zz;
  return r;
}

struct Quaternions {
  Lanes w, x, y, z;
};

// The rotation of q, whatever its length, by a division: no square root on the way to the stress.
INCISE_LANES M3 rotation_of(const Quaternions& q) {
  const Lanes inverse_norm2 = 1 / (q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  M3 rotation = homogeneous_rotation_of(q.w, q.x, q.y, q.z);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      rotation.m[i][j] *= inverse_norm2;
  return rotation;
}

// q at unit length.
INCISE_LANES Quaternions normalised(const Quaternions& q) {
  const Lanes n = 1 / lanes_sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  return {q.w * n, q.x * n, q.y * n, q.z * n};
}

// Newton on the rotation maximising tr(R^T F) from q (the header). Returns the lanes that
// converged: those whose last step was below kStepTolerance with a positive definite Hessian.
// Lanes outside `active` (slots without an element) count as converged from the start. Adds the
// iterations it ran to `iterations`.
//
// No square root lies on the chain from one iterate to the next, and its divisions run beside
// other work: q is kept unnormalised, R = R~(q) / |q|^2 with R~ the homogeneous rotation of q
// (1 / |q|^2 computed beside R~), and the step theta = adj(H) w / det H enters q as the
// quaternion (2 det H, adj(H) w) / (tr H)^3, which turns R by the same rotation as
// (1, theta / 2); the gradient step w / |tr A| enters as (2, w / |tr A|). Both divisors are known
// as soon as A is. A Newton step shrinks |q| by a factor between about 2e-12 (det H is at least
// 1e-12 (tr H)^3 where it is taken) and 0.08 (det H <= (tr H / 3)^3, |v| <= d), so after
// kMaxNewton steps |q|^2 is at least about 1e-188: far from underflow, and R~(q) / |q|^2 is as
// exact as at unit length. q is normalised before it is stored.
INCISE_LANES LaneMask polar_newton(const M3& f, LaneMask active, Quaternions& q, int& iterations) {
  // A step below 1e-6 rad leaves an error of its square (quadratic convergence), 1e-12: done. A
  // tet whose rotation changed by less than that since the last call takes one iteration.
  constexpr Real kStepTolerance2 = 1e-12;
  LaneMask converged = ~active;
  for (int iteration = 0; iteration < CorotationalBatch::kMaxNewton; ++iteration) {
    ++iterations;
    const M3 a = transpose_times(rotation_of(q), f);
    const Lanes w0 = a.m[2][1] - a.m[1][2];
    const Lanes w1 = a.m[0][2] - a.m[2][0];
    const Lanes w2 = a.m[1][0] - a.m[0][1];
    const Lanes trace = a.m[0][0] + a.m[1][1] + a.m[2][2];
    // H = tr(A) I - sym(A), its adjugate and determinant.
    const Lanes h00 = a.m[1][1] + a.m[2][2];
    const Lanes h11 = a.m[0][0] + a.m[2][2];
    const Lanes h22 = a.m[0][0] + a.m[1][1];
    const Lanes h01 = Real(-0.5) * (a.m[0][1] + a.m[1][0]);
    const Lanes h02 = Real(-0.5) * (a.m[0][2] + a.m[2][0]);
    const Lanes h12 = Real(-0.5) * (a.m[1][2] + a.m[2][1]);
    const Lanes c00 = h11 * h22 - h12 * h12;
    const Lanes c01 = h02 * h12 - h01 * h22;
    const Lanes c02 = h01 * h12 - h02 * h11;
    const Lanes c11 = h00 * h22 - h02 * h02;
    const Lanes c12 = h01 * h02 - h00 * h12;
    const Lanes c22 = h00 * h11 - h01 * h01;
    const Lanes det = h00 * c00 + h01 * c01 + h02 * c02;
    const Lanes scale = h00 + h11 + h22;
    // Sylvester's criterion, with the determinant away from zero relative to H's size.
    const LaneMask definite =
        (h00 > 0) & (c22 > 0) & (scale > 0) & (det > Real(1e-12) * scale * scale * scale);
    // theta = v / d with d > 0, and the step's scale g (above).
    const Lanes abs_trace = select(trace < 0, -trace, trace);
    const Lanes gradient_d = abs_trace + Real(1e-12) * (scale + 1);
    const Lanes inverse_g =
        1 / select(converged, splat(1), select(definite, scale * scale * scale, gradient_d));
    Lanes d = select(definite, det, gradient_d);
    Lanes v0 = select(definite, c00 * w0 + c01 * w1 + c02 * w2, w0);
    Lanes v1 = select(definite, c01 * w0 + c11 * w1 + c12 * w2, w1);
    Lanes v2 = select(definite, c02 * w0 + c12 * w1 + c22 * w2, w2);
    // Lanes already converged stay where they are.
    d = select(converged, splat(1), d);
    v0 = select(converged, splat(0), v0);
    v1 = select(converged, splat(0), v1);
    v2 = select(converged, splat(0), v2);
    const Lanes v_norm2 = v0 * v0 + v1 * v1 + v2 * v2;
    const Lanes d2 = d * d;
    // At most a radian per step (rare: a cold start or a fast turn).
    const LaneMask long_step = v_norm2 > d2;
    if (any(long_step)) {
      const Lanes shorten = select(long_step, d / lanes_sqrt(v_norm2), splat(1));
      v0 *= shorten;
      v1 *= shorten;
      v2 *= shorten;
    }
    // q <- q (2 d, v) / g: R <- R exp([theta]) to second order.
    const Lanes dw = 2 * d * inverse_g;
    v0 *= inverse_g;
    v1 *= inverse_g;
    v2 *= inverse_g;
    const Quaternions p = q;
    q.w = p.w * dw - p.x * v0 - p.y * v1 - p.z * v2;
    q.x = p.w * v0 + p.x * dw + p.y * v2 - p.z * v1;
    q.y = p.w * v1 - p.x * v2 + p.y * dw + p.z * v0;
    q.z = p.w * v2 + p.x * v1 - p.y * v0 + p.z * dw;
    converged |= definite & (v_norm2 < kStepTolerance2 * d2);
    if (all(converged)) break;
  }
  return converged;
}

Mat3 lane_matrix(const M3& a, int l) {
  Mat3 m;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      m(i, j) = a.m[i][j][l];
  return m;
}

void set_lane(M3& a, int l, const Mat3& m) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      a.m[i][j][l] = m(i, j);
}

// Ds = [x1 - x0, x2 - x0, x3 - x0] of four tets, node[lane][tet node] into x (#nodes by 3), as an
// M3 (lanes.h's edge_lanes).
INCISE_LANES M3 edge_matrix_of(const Real* x, const int (&node)[4][4]) {
  Lanes columns[3][4];
  edge_lanes(x, node, columns);
  M3 ds;
  for (int k = 0; k < 3; ++k)
    for (int i = 0; i < 3; ++i)
      ds.m[i][k] = columns[k][i];
  return ds;
}

struct BatchView {
  int padded;
  const int* const* nodes;
  const Real* const* rest_inverse;
  const Real* volume;
  const Real* mu;
  const Real* lambda;
  const Real* beta;
  Real* const* rotation;
};

struct ForceTotals {
  ModelHealth health;
  int fallbacks = 0;
  int newton_iterations = 0;  // summed over blocks of four tets
};

// The forces of four tets from `base` (CorotationalKernel::stress plus the damping of
// TetFemModel::add_forces, per lane).
template <bool kPolar>
INCISE_LANES void forces_of_four(const BatchView& b, int base, const Real* x, const Real* v,
                                 Real* f, ForceTotals& totals) {
  const Lanes volume = load(b.volume + base);
  const LaneMask alive = volume > 0;
  M3 rest_inverse;
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 3; ++j)
      rest_inverse.m[k][j] = load(b.rest_inverse[3 * k + j] + base);
  int node[4][4];  // [lane][tet node]
  for (int a = 0; a < 4; ++a)
    for (int l = 0; l < 4; ++l)
      node[l][a] = b.nodes[a][base + l];

  // F = Ds Dm^-1 and, for the damping, dF/dt = (dDs/dt) Dm^-1.
  const M3 deformation = times(edge_matrix_of(x, node), rest_inverse);
  const Lanes j = determinant(deformation);
  totals.health.inverted_elements += count(alive & (j <= 0));

  M3 rotation;
  M3 stretch;
  LaneMask degenerate = {0, 0, 0, 0};
  if constexpr (kPolar) {
    Quaternions q{load(b.rotation[0] + base), load(b.rotation[1] + base),
                  load(b.rotation[2] + base), load(b.rotation[3] + base)};
    const LaneMask converged = polar_newton(deformation, alive, q, totals.newton_iterations);
    rotation = rotation_of(q);
    q = normalised(q);
    if (!all(converged)) {
      for (int l = 0; l < 4; ++l) {
        if (converged[l] || !alive[l]) continue;
        const Mat3 r = polar_rotation(lane_matrix(deformation, l));
        set_lane(rotation, l, r);
        const Eigen::Quaternion<Real> fallback(r);
        q.w[l] = fallback.w();
        q.x[l] = fallback.x();
        q.y[l] = fallback.y();
        q.z[l] = fallback.z();
        ++totals.fallbacks;
      }
    }
    store(b.rotation[0] + base, q.w);
    store(b.rotation[1] + base, q.x);
    store(b.rotation[2] + base, q.y);
    store(b.rotation[3] + base, q.z);
    stretch = transpose_times(rotation, deformation);
  } else {
    // Gram-Schmidt of F's columns (qr_rotation), its degenerate lanes from the scalar code.
    const Lanes f1x = deformation.m[0][0], f1y = deformation.m[1][0], f1z = deformation.m[2][0];
    const Lanes f2x = deformation.m[0][1], f2y = deformation.m[1][1], f2z = deformation.m[2][1];
    const Lanes length1 = lanes_sqrt(f1x * f1x + f1y * f1y + f1z * f1z);
    const Lanes inverse1 = 1 / select(length1 > 1e-12, length1, splat(1));
    const Lanes r1x = f1x * inverse1, r1y = f1y * inverse1, r1z = f1z * inverse1;
    const Lanes along = r1x * f2x + r1y * f2y + r1z * f2z;
    const Lanes px = f2x - along * r1x, py = f2y - along * r1y, pz = f2z - along * r1z;
    const Lanes length2 = lanes_sqrt(px * px + py * py + pz * pz);
    const Lanes f2_length = lanes_sqrt(f2x * f2x + f2y * f2y + f2z * f2z);
    const LaneMask framed = (length1 > 1e-12) & (length2 > 1e-12 * (1 + f2_length));
    const Lanes inverse2 = 1 / select(framed, length2, splat(1));
    const Lanes r2x = px * inverse2, r2y = py * inverse2, r2z = pz * inverse2;
    rotation.m[0][0] = r1x;
    rotation.m[1][0] = r1y;
    rotation.m[2][0] = r1z;
    rotation.m[0][1] = r2x;
    rotation.m[1][1] = r2y;
    rotation.m[2][1] = r2z;
    rotation.m[0][2] = r1y * r2z - r1z * r2y;
    rotation.m[1][2] = r1z * r2x - r1x * r2z;
    rotation.m[2][2] = r1x * r2y - r1y * r2x;
    stretch = transpose_times(rotation, deformation);
    stretch.m[1][0] = stretch.m[2][0] = stretch.m[2][1] = splat(0);
    degenerate = ~framed & alive;
    if (any(degenerate)) {
      for (int l = 0; l < 4; ++l) {
        if (!degenerate[l]) continue;
        const QrRotation qr = qr_rotation(lane_matrix(deformation, l));
        set_lane(rotation, l, qr.rotation);
        set_lane(stretch, l, qr.upper);
        ++totals.fallbacks;
      }
    }
  }
  const Lanes abs_j = select(j < 0, -j, j);
  totals.health.degenerate_elements +=
      count(alive & (degenerate | ~(abs_j >= kDegenerateVolumeRatio)));

  const Lanes mu = load(b.mu + base);
  const Lanes lambda = load(b.lambda + base);
  M3 sigma = linear_stress_of(stretch, 1, mu, lambda);
  if constexpr (!kPolar) {
    // P = R (C(eps) - M), M the dR/dF term (corotational_fem.h); zero where the frame fell back.
    const M3 a = times_transpose(sigma, stretch);
    const Lanes skew10 = a.m[1][0] - a.m[0][1];
    const Lanes skew20 = a.m[2][0] - a.m[0][2];
    const Lanes skew21 = a.m[2][1] - a.m[1][2];
    const Lanes u00 = select(degenerate, splat(1), stretch.m[0][0]);
    const Lanes u11 = select(degenerate, splat(1), stretch.m[1][1]);
    const Lanes keep = select(degenerate, splat(0), splat(1));
    sigma.m[1][0] -= keep * (skew10 / u00);
    sigma.m[2][0] -= keep * (skew20 / u00 - skew21 * stretch.m[0][1] / (u00 * u11));
    sigma.m[2][1] -= keep * (skew21 / u11);
  }
  M3 stress = times(rotation, sigma);

  // Kelvin-Voigt damping in the frame F: beta min(1, 3 / |F|^2) F C(sym(F^T dF/dt)).
  const Lanes beta = load(b.beta + base);
  if (any(beta > 0)) {
    const M3 rate = times(edge_matrix_of(v, node), rest_inverse);
    const M3 viscous =
        times(deformation, linear_stress_of(transpose_times(deformation, rate), 0, mu, lambda));
    Lanes norm2 = splat(0);
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k)
        norm2 += deformation.m[i][k] * deformation.m[i][k];
    const Lanes factor = beta * select(norm2 > 3, 3 / norm2, splat(1));
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k)
        stress.m[i][k] += factor * viscous.m[i][k];
  }

  // [f1 f2 f3] = -V0 P Dm^-T, f0 = -(f1 + f2 + f3); back from lanes to each tet's (x, y, z, 0).
  const M3 h = times_transpose(stress, rest_inverse);
  const Lanes scale = -volume;
  Lanes nodal[4][3];  // [tet node][coordinate], lanes
  for (int i = 0; i < 3; ++i) {
    nodal[0][i] = splat(0);
    for (int k = 0; k < 3; ++k) {
      nodal[k + 1][i] = scale * h.m[i][k];
      nodal[0][i] -= nodal[k + 1][i];
    }
  }
  for (int a = 0; a < 4; ++a) {
    Lanes per_lane[4];
    transpose(nodal[a][0], nodal[a][1], nodal[a][2], splat(0), per_lane);
    for (int l = 0; l < 4; ++l)
      if (alive[l]) add_point(f + 3 * node[l][a], per_lane[l]);
  }
}

// The kernels' entry points, compiled twice: for x86-64-v3 (AVX2, four doubles a register) and
// the baseline (SSE2); the loader picks one by the processor (GCC function multiversioning).
[[gnu::target_clones("arch=x86-64-v3", "default")]] ForceTotals polar_forces(const BatchView& b,
                                                                             const Real* x,
                                                                             const Real* v,
                                                                             Real* f) {
  ForceTotals totals;
  for (int base = 0; base < b.padded; base += 4)
    forces_of_four<true>(b, base, x, v, f, totals);
  return totals;
}

[[gnu::target_clones("arch=x86-64-v3", "default")]] ForceTotals qr_forces(const BatchView& b,
                                                                          const Real* x,
                                                                          const Real* v, Real* f) {
  ForceTotals totals;
  for (int base = 0; base < b.padded; base += 4)
    forces_of_four<false>(b, base, x, v, f, totals);
  return totals;
}

}  // namespace

void CorotationalBatch::resize(int slots) {
  slots_ = slots;
  padded_ = (slots + kLanes - 1) / kLanes * kLanes;
  const std::size_t n = static_cast<std::size_t>(padded_);
  for (auto& a : nodes_)
    a.resize(n, 0);
  for (auto& a : rest_inverse_)
    a.resize(n, 0);
  volume_.resize(n, 0);
  mu_.resize(n, 0);
  lambda_.resize(n, 0);
  beta_.resize(n, 0);
  for (auto& a : rotation_)
    a.resize(n, 0);
  // The padding holds no element, whatever a larger slot count left there.
  for (int t = slots_; t < padded_; ++t)
    clear_slot(t);
}

void CorotationalBatch::clear_slot(int t) {
  const std::size_t s = static_cast<std::size_t>(t);
  for (auto& a : nodes_)
    a[s] = 0;
  for (int k = 0; k < 9; ++k)
    rest_inverse_[k][s] = k % 4 == 0 ? 1 : 0;
  volume_[s] = mu_[s] = lambda_[s] = beta_[s] = 0;
  rotation_[0][s] = 1;
  rotation_[1][s] = rotation_[2][s] = rotation_[3][s] = 0;
}

void CorotationalBatch::set_slot(const TetElements& elements, int t) {
  clear_slot(t);
  if (!elements.alive(t)) return;
  const std::size_t s = static_cast<std::size_t>(t);
  for (int a = 0; a < 4; ++a)
    nodes_[a][s] = elements.tets(t, a);
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 3; ++j)
      rest_inverse_[3 * k + j][s] = elements.rest_inverse[s](k, j);
  volume_[s] = elements.rest_volume(t);
  mu_[s] = elements.lame[s].mu;
  lambda_[s] = elements.lame[s].lambda;
  beta_[s] = elements.damping(t);
}

void CorotationalBatch::update_material(const TetElements& elements, int t) {
  const std::size_t s = static_cast<std::size_t>(t);
  if (!elements.alive(t)) return;
  mu_[s] = elements.lame[s].mu;
  lambda_[s] = elements.lame[s].lambda;
  beta_[s] = elements.damping(t);
}

void CorotationalBatch::assign(const TetElements& elements) {
  resize(elements.num_tets());
  for (int t = 0; t < slots_; ++t)
    set_slot(elements, t);
}

void CorotationalBatch::update(const TetElements& elements, std::span<const int> slots) {
  if (elements.num_tets() != slots_) resize(elements.num_tets());
  for (const int t : slots)
    set_slot(elements, t);
}

ModelHealth CorotationalBatch::add_forces(RotationExtraction extraction, const Points& x,
                                          const Points& v, Points& f) {
  const int* nodes[4] = {nodes_[0].data(), nodes_[1].data(), nodes_[2].data(), nodes_[3].data()};
  const Real* rest_inverse[9];
  for (int k = 0; k < 9; ++k)
    rest_inverse[k] = rest_inverse_[k].data();
  Real* rotation[4] = {rotation_[0].data(), rotation_[1].data(), rotation_[2].data(),
                       rotation_[3].data()};
  const BatchView view{padded_,    nodes,          rest_inverse, volume_.data(),
                       mu_.data(), lambda_.data(), beta_.data(), rotation};
  const ForceTotals totals = extraction == RotationExtraction::polar
                                 ? polar_forces(view, x.data(), v.data(), f.data())
                                 : qr_forces(view, x.data(), v.data(), f.data());
  fallbacks_ = totals.fallbacks;
  newton_iterations_ =
      padded_ > 0 ? static_cast<Real>(totals.newton_iterations) * kLanes / padded_ : 0;
  return totals.health;
}

Mat3 CorotationalBatch::rotation(int t) const {
  const std::size_t s = static_cast<std::size_t>(t);
  const Real w = rotation_[0][s], x = rotation_[1][s], y = rotation_[2][s], z = rotation_[3][s];
  Mat3 r;
  r << 1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),  //
      2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),   //
      2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y);
  return r;
}

}  // namespace incise::sim
