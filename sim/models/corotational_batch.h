#pragma once
// Corotational FEM's per-tet work (corotational_fem.h) over structure-of-arrays element data,
// vectorised across tets: four tets share one SIMD register of doubles per quantity (AVX2 where
// the processor has it, chosen at load time; SSE2 pairs otherwise). The same physics as
// CorotationalKernel, equal to it to round-off, several times faster (docs/benchmarks.md,
// bench_kernels).
//
// Polar rotations are warm-started: each slot keeps its last rotation R0 (a unit quaternion) and
// the step is Newton's method on the rotation maximising tr(R^T F) over proper rotations, which is
// the polar rotation of corotational_fem.h for every F, inverted ones included (its maximiser is
// U diag(1, 1, det(U V^T)) V^T, the sign-fixed SVD). With A = R^T F, the gradient in the rotation
// vector theta (R <- R exp([theta])) is w = vee(A - A^T) and the Hessian -(tr(A) I - sym(A)), so
//   theta = (tr(A) I - sym(A))^-1 w
// converges quadratically while that matrix is positive definite (near the maximiser it is:
// its eigenvalues are sums of two singular values). From last step's rotation that is two or three
// iterations. Where it is not positive definite the step is the gradient scaled by 1 / |tr A|
// (Mueller et al. 2016, "A robust method to extract the rotational part of deformations"), at most
// one radian. A tet not converged after kMaxNewton iterations (a cold start at a half turn, an F
// flat to a line) takes the scalar polar_rotation, whose result also becomes its warm start.
//
// Not thread-safe for one batch (add_forces updates the warm starts); allocation-free after
// assign().
#include <span>
#include <vector>

#include "sim/core/types.h"
#include "sim/models/model.h"
#include "sim/models/rotation_extraction.h"
#include "sim/models/tet_elements.h"

namespace incise::sim {

class CorotationalBatch {
 public:
  static constexpr int kLanes = 4;
  static constexpr int kMaxNewton = 8;

  // Every slot of elements (dead slots take no part).
  void assign(const TetElements& elements);
  // Slots of elements whose element or material changed (update_elements, soften_element); they
  // restart from the identity rotation. The slot count may have grown.
  void update(const TetElements& elements, std::span<const int> slots);

  // Slot t's Lame parameters and damping changed (soften_element); its warm start stays.
  void update_material(const TetElements& elements, int t);

  // f += the elastic and Kelvin-Voigt damping forces at positions x and velocities v (#nodes by
  // 3), as TetFemModel<CorotationalKernel>::add_forces. Returns the element health.
  ModelHealth add_forces(RotationExtraction extraction, const Points& x, const Points& v,
                         Points& f);

  // Slot t's rotation: the warm start, which after add_forces with polar rotations is the
  // rotation that call used (NodalPressureFem's second pass reads it).
  Mat3 rotation(int t) const;

  // How many tets the last add_forces sent to the scalar rotation (for tests and benchmarks).
  int last_fallbacks() const { return fallbacks_; }
  // Newton iterations per tet in the last add_forces with polar rotations (each block of four
  // iterates until its last tet converged).
  Real last_newton_iterations() const { return newton_iterations_; }

 private:
  void resize(int slots);
  void set_slot(const TetElements& elements, int t);
  void clear_slot(int t);

  int slots_ = 0;                      // element slots
  int padded_ = 0;                     // slots_ rounded up to kLanes
  std::vector<int> nodes_[4];          // #padded node indices; 0 in a slot without an element
  std::vector<Real> rest_inverse_[9];  // #padded Dm^-1 entries, row-major (k, j) at 3 k + j
  std::vector<Real> volume_;           // #padded V0 [m^3]; 0 marks a slot without an element
  std::vector<Real> mu_, lambda_;      // #padded Lame parameters [Pa]
  std::vector<Real> beta_;             // #padded damping [s]
  std::vector<Real> rotation_[4];      // #padded warm starts: unit quaternions (w, x, y, z)
  int fallbacks_ = 0;
  Real newton_iterations_ = 0;
};

}  // namespace incise::sim
