#pragma once
// Which faces of a tissue's boundary are walls that a cut opened, and which are the organ's own
// surface (its capsule, however refined), so that the picture can show an opened cut in the
// interior's colour. A face is a cut wall when its rest centroid lies off the boundary the tissue
// had at rest before anything changed it: a cut makes faces inside the rest volume, while
// refinement splits boundary faces within their own planes and coarsening restores them.
#include <cstdint>
#include <unordered_map>
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
  // its answer without a search, so a call costs a hash per face plus a search per new face.
  void classify(const Points& rest, const BoundarySurface& surface,
                std::vector<std::uint8_t>& flags);

  // How far a rest centroid may lie from the starting boundary and still be on it [m]: far above
  // the round-off of a split face's centroid (1e-17 m on a 10 cm organ), far below any cut face's
  // depth.
  static constexpr Real kOnSurface = 1e-7;

 private:
  struct Key {
    Real x, y, z;
    bool operator==(const Key&) const = default;
  };
  struct KeyHash {
    std::size_t operator()(const Key& k) const;
  };

  Points rest_;
  collide::SurfaceBvh tree_;
  std::unordered_map<Key, std::uint8_t, KeyHash> known_, next_;
  std::vector<int> slots_;  // scratch of the search
};

}  // namespace incise::sim::surgery
