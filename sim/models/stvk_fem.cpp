#include "sim/models/stvk_fem.h"

#include <utility>

namespace incise::sim {

template class TetFemModel<StVenantKirchhoffKernel>;

StVenantKirchhoffFem::StVenantKirchhoffFem(const TetMesh& mesh,
                                           std::vector<ElementMaterial> materials)
    : TetFemModel(mesh, std::move(materials), StVenantKirchhoffKernel{}) {}

}  // namespace incise::sim
