#pragma once
// The rotation of a tet's deformation gradient F, for corotational FEM (Physically Realistic FEM,
// section 2.4 and figure 1). Both return a proper rotation (det R = +1) for any F, also flat or
// inverted ones.
#include "sim/core/types.h"

namespace incise::sim {

// How a corotational model takes R from F.
enum class RotationExtraction {
  qr,     // Gram-Schmidt of F's columns: cheaper, depends on the tet's node order
  polar,  // the polar decomposition (SVD): the rotation nearest to F, no ordering anisotropy
};

// F = R U by Gram-Schmidt of F's columns (Physically Realistic FEM, "QR decomposition"): r1 along
// f1, r2 in the plane of f1 and f2, r3 = r1 x r2, so that the frame is right-handed even for an
// inverted F (then U's last diagonal entry is negative). U is upper triangular with
// U(0,0), U(1,1) > 0.
struct QrRotation {
  Mat3 rotation = Mat3::Identity();  // R
  Mat3 upper = Mat3::Identity();     // U = R^T F
  bool degenerate = false;  // f1 = 0 or f2 parallel to f1: no frame; R is then the polar rotation
};
QrRotation qr_rotation(const Mat3& deformation);

// The rotation R of the polar decomposition F = R S, the rotation nearest to F. From the SVD
// F = U Sigma V^T with the signs fixed so that U and V are rotations (an inverted F keeps a
// negative last singular value, as in Irving et al. 2004, "Invertible finite elements"):
// R = U V^T, and S = V Sigma V^T is symmetric.
// Computed from the eigen decomposition of F^T F in closed form (falls back to the SVD for an F
// flat to a line or a point).
Mat3 polar_rotation(const Mat3& deformation);
// The same rotation by Eigen's Jacobi SVD: slower (it iterates), the reference for the above.
Mat3 polar_rotation_svd(const Mat3& deformation);

}  // namespace incise::sim
