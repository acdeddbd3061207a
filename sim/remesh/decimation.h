#pragma once

// The decimation driver (Paloc 2006, "Local mesh decimation"): inserted vertices
// outside the region to keep refined are removed, a little per call, and a vertex that cannot be
// removed now (kCannotRemoveNow) goes to the back of the list and is retried later.

#include <deque>
#include <functional>
#include <vector>

#include "sim/remesh/remesh_mesh.h"
#include "sim/remesh/size_field.h"
#include "sim/remesh/state_transfer.h"
#include "sim/remesh/vertex_removal.h"

namespace incise::sim::remesh {

struct DecimationStats {
  int removed = 0;
  // Attempts answered kCannotRemoveNow; the vertex was queued again at the back.
  int deferred = 0;
  // Queue entries dropped without an attempt: the vertex is gone, or back in the region.
  int dropped = 0;
  // The call ended because every queued vertex was tried once since the last removal, all
  // refused: nothing can be removed now; call again after the mesh has changed.
  bool stuck = false;
};

class Decimator {
 public:
  using RemoveFunction = std::function<RemoveResult(RemeshMesh&, int vertex)>;

  // Without `remove`, vertices are removed by remove_vertex under the altitude floor below;
  // tests may give their own function (to refuse on purpose), which the floor does not reach.
  explicit Decimator(RemoveFunction remove = {});

  // The smallest altitude a removal may leave [m] (remove_vertex's min_altitude; 0, the
  // default: none). Set it to the refinement's floor (or below the input mesh's own smallest
  // altitude, if that is lower) so that coarsening never lowers the stable time step either.
  // Throws std::invalid_argument for a negative or non-finite value.
  void set_altitude_floor(Real min_altitude);
  Real altitude_floor() const { return altitude_floor_; }

  // Queues (at the back) every alive inserted vertex whose rest point `keep_refined` maps to
  // +infinity and that is not queued yet; returns how many were added. O(#vertex slots), so call
  // it when the region has moved rather than every frame. For hysteresis, give a keep region
  // larger than the refinement region, so that a vertex is not removed and re-inserted as the
  // region moves by a little.
  int collect(const RemeshMesh& mesh, const SizeField& keep_refined);

  // At most max_attempts removal attempts (>= 0) from the front of the queue: bounded work per
  // call, so that it can run a little every frame. A vertex that is gone, original, or whose rest
  // point is back in `keep_refined`'s region is dropped from the queue without an attempt.
  DecimationStats step(RemeshMesh& mesh, const SizeField& keep_refined, int max_attempts,
                       const RemeshListener& listener = {});

  int pending() const { return static_cast<int>(queue_.size()); }

 private:
  RemoveFunction remove_;
  Real altitude_floor_ = 0;
  std::deque<int> queue_;
  std::vector<char> queued_;  // by vertex slot
};

}  // namespace incise::sim::remesh
