#include "sim/remesh/decimation.h"

#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace incise::sim::remesh {

Decimator::Decimator(RemoveFunction remove) : remove_(std::move(remove)) {}

void Decimator::set_altitude_floor(Real min_altitude) {
  if (!(min_altitude >= 0 && std::isfinite(min_altitude))) {
    throw std::invalid_argument("decimation altitude floor must be finite and >= 0, got " +
                                std::to_string(min_altitude));
  }
  altitude_floor_ = min_altitude;
}

int Decimator::collect(const RemeshMesh& mesh, const SizeField& keep_refined) {
  queued_.resize(static_cast<size_t>(mesh.num_vertex_slots()), 0);
  int added = 0;
  for (int v = mesh.num_original_vertices(); v < mesh.num_vertex_slots(); ++v) {
    if (!mesh.vertex_alive(v) || queued_[static_cast<size_t>(v)]) continue;
    if (std::isfinite(keep_refined(mesh.point(v)))) continue;
    queue_.push_back(v);
    queued_[static_cast<size_t>(v)] = 1;
    ++added;
  }
  return added;
}

DecimationStats Decimator::step(RemeshMesh& mesh, const SizeField& keep_refined, int max_attempts,
                                const RemeshListener& listener) {
  if (max_attempts < 0) throw std::invalid_argument("decimation max_attempts must be >= 0");
  DecimationStats stats;
  int attempts = 0;
  int refused_in_a_row = 0;
  while (!queue_.empty() && attempts < max_attempts) {
    if (refused_in_a_row >= static_cast<int>(queue_.size())) {
      stats.stuck = true;
      break;
    }
    const int v = queue_.front();
    queue_.pop_front();
    // A slot freed and reused by a later insertion holds a vertex that is just as removable
    // if it is outside the region, so the checks below are all that is needed.
    if (v >= mesh.num_vertex_slots() || !mesh.vertex_alive(v) || mesh.is_original(v) ||
        std::isfinite(keep_refined(mesh.point(v)))) {
      queued_[static_cast<size_t>(v)] = 0;
      ++stats.dropped;
      continue;
    }
    ++attempts;
    const RemoveResult result =
        remove_ ? remove_(mesh, v) : remove_vertex(mesh, v, altitude_floor_);
    if (listener.on_removal) listener.on_removal(v, result);
    if (result.status == RemoveStatus::kRemoved) {
      queued_[static_cast<size_t>(v)] = 0;
      ++stats.removed;
      refused_in_a_row = 0;
    } else {
      queue_.push_back(v);  // retried later, after the others
      ++stats.deferred;
      ++refused_in_a_row;
    }
  }
  return stats;
}

}  // namespace incise::sim::remesh
