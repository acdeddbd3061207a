#include "sim/models/linear_fem.h"

#include <utility>

namespace incise::sim {

template class TetFemModel<LinearKernel>;

LinearFem::LinearFem(const TetMesh& mesh, std::vector<ElementMaterial> materials)
    : TetFemModel(mesh, std::move(materials), LinearKernel{}) {}

}  // namespace incise::sim
