#pragma once
// Internal to HybridCondensedModel (sim/models/hybrid_condensed_*.cpp): the body split into its
// regions and the far field's matrices split into blocks, with the error prefix of every file of
// the model.

#include <string>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/Sparse>

#include "sim/core/types.h"
#include "sim/mesh/tet_mesh.h"

namespace incise::sim {

using SparseMatrix = Eigen::SparseMatrix<Real>;
using Triplets = std::vector<Eigen::Triplet<Real>>;

// "HybridCondensedModel: " + what, for the model's error messages.
inline std::string where(const char* what) {
  return std::string("HybridCondensedModel: ") + what;
}

// A tet's nodes sorted ascending: the same tet whatever its row's node order.
Eigen::RowVector4i sorted_tet(const Tets& tets, Eigen::Index row);

// The mesh's rest state with only the tets whose flag equals `keep`.
TetMesh region_mesh(const TetMesh& mesh, const std::vector<char>& operational, bool keep);

// The far field's matrix (K or D, over all mesh degrees of freedom) split by the local numbering
// `local` (retained dofs first, then interior ones; -1 outside the far field).
struct Partition {
  Eigen::MatrixXd ss;
  SparseMatrix si, is, ii;
};

Partition partition(const Triplets& entries, const std::vector<int>& local, Eigen::Index s_dofs,
                    Eigen::Index i_dofs);

}  // namespace incise::sim
