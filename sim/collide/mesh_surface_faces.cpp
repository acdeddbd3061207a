#include "sim/collide/mesh_surface_faces.h"

#include <stdexcept>
#include <string>

namespace incise::sim::collide {

Triangles mesh_surface_faces(const BoundarySurface& surface) {
  const int num_vertices = static_cast<int>(surface.nodes.size());
  Triangles faces(surface.faces.rows(), 3);
  for (int f = 0; f < surface.faces.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int local = surface.faces(f, k);
      if (local < 0 || local >= num_vertices) {
        throw std::invalid_argument("mesh_surface_faces: face " + std::to_string(f) +
                                    " has vertex " + std::to_string(local) + " outside [0, " +
                                    std::to_string(num_vertices) + ")");
      }
      faces(f, k) = surface.nodes[local];
    }
  }
  return faces;
}

}  // namespace incise::sim::collide
