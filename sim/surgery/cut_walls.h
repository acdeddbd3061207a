#pragma once
// Which faces of a tissue's boundary are walls that a cut opened, and which are the organ's own
// surface (its capsule, however refined), so that the picture can show an opened cut in the
// interior's colour. A face is a cut wall when its rest centroid lies off the boundary the tissue
// had at rest before anything changed it: a cut makes faces inside the rest volume, while
// refinement splits boundary faces within their own planes and coarsening restores them.
#include <cstdint>
#include <vector>

#include "sim/collide/surface_bvh.h"
#include "sim/core/types.h"
#include "sim/mesh/boundary_surface.h"

namespace incise::sim::surgery {

class CutWalls {
 public:
  // The tissue's boundary at the start: the rest positions (#nodes by 3 [m]) and its triangles
  // as node indices. Throws std::invalid_argument as SurfaceBvh::build does.
  CutWalls(const Points& rest, const Triangles& faces);

  // flags[f] = 1 for a cut wall, 0 for the capsule, per face of surface (whose nodes index rest,
  // the mesh's rest positions now). A face whose rest centroid was seen at the last call keeps
  // its answer without a search: a call costs a sort of the faces' centroids and a binary search
  // per face, plus a tree search per new face; no allocation once its arrays have grown.
  void classify(const Points& rest, const BoundarySurface& surface,
                std::vector<std::uint8_t>& flags);

  // How far a rest centroid may lie from the starting boundary and still be on it [m]: far above
  // the round-off of a split face's centroid (1e-17 m on a 10 cm organ), far below any cut face's
  // depth.
  static constexpr Real kOnSurface = 1e-7;

 private:
  // A rest centroid and its answer, ordered by the centroid's coordinates.
  struct Entry {
    Real x, y, z;
    std::uint8_t wall;
    bool operator<(const Entry& o) const {
      return x != o.x ? x < o.x : y != o.y ? y < o.y : z < o.z;
    }
  };

  Points rest_;
  collide::SurfaceBvh tree_;
  std::vector<Entry> known_, next_;  // sorted: the last call's faces, this call's
  std::vector<int> slots_;           // scratch of the search
};

}  // namespace incise::sim::surgery
