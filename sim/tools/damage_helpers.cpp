// The two free helpers of damage_tracker.h: deepest_contact (per step, for record_contacts) and
// parents_by_rest_centroid (per topology change, for update_elements).
#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

#include "sim/tools/damage_strain.h"
#include "sim/tools/damage_tracker.h"

namespace incise::sim::tools {

Real deepest_contact(std::span<const collide::Contact> contacts,
                     std::span<const char> triangle_is_protected) {
  Real deepest = 0;
  for (const collide::Contact& c : contacts) {
    if (!triangle_is_protected.empty()) {
      if (c.triangle < 0 || static_cast<std::size_t>(c.triangle) >= triangle_is_protected.size())
        throw std::invalid_argument("deepest_contact: contact triangle " +
                                    std::to_string(c.triangle) + " is outside [0, " +
                                    std::to_string(triangle_is_protected.size()) + ")");
      if (!triangle_is_protected[static_cast<std::size_t>(c.triangle)]) continue;
    }
    deepest = std::max(deepest, c.depth);
  }
  return deepest;
}

void parents_by_rest_centroid(const Points& rest, const Tets& old_tets,
                              const std::vector<char>& old_alive, const Tets& new_tets,
                              std::span<const int> changed, std::vector<int>& parents) {
  auto fail = [](const std::string& what) {
    throw std::invalid_argument("parents_by_rest_centroid: " + what);
  };
  if (old_alive.size() != static_cast<std::size_t>(old_tets.rows()))
    fail("old_alive has " + std::to_string(old_alive.size()) + " entries for " +
         std::to_string(old_tets.rows()) + " old tet slots");
  auto corner = [&](const Tets& tets, int s, int k) {
    const int node = tets(s, k);
    if (node < 0 || node >= rest.rows())
      fail("a tet holds node " + std::to_string(node) + ", outside [0, " +
           std::to_string(rest.rows()) + ")");
    return row3(rest, node);
  };
  // Dm^-1 and the bounding box of every alive old tet, once.
  const auto old_slots = static_cast<std::size_t>(old_tets.rows());
  std::vector<Mat3> inverse(old_slots, Mat3::Zero());
  std::vector<Box3> bounds(old_slots);
  std::vector<char> usable(old_slots, 0);
  for (int t = 0; t < old_tets.rows(); ++t) {
    const auto i = static_cast<std::size_t>(t);
    if (!old_alive[i]) continue;
    for (int k = 0; k < 4; ++k)
      bounds[i].extend(corner(old_tets, t, k));
    usable[i] = rest_edge_inverse(corner(old_tets, t, 0), corner(old_tets, t, 1),
                                  corner(old_tets, t, 2), corner(old_tets, t, 3), inverse[i]) > 0;
  }
  // A centroid on a shared face (it cannot be for a piece of one old tet, but can for a
  // decimated tet) is inside both within rounding; the deepest one wins.
  constexpr Real kTolerance = 1e-9;
  parents.assign(changed.size(), -1);
  for (std::size_t k = 0; k < changed.size(); ++k) {
    const int s = changed[k];
    if (s < 0 || s >= new_tets.rows())
      fail("changed slot " + std::to_string(s) + " is outside [0, " +
           std::to_string(new_tets.rows()) + ")");
    Vec3 centroid = Vec3::Zero();
    for (int j = 0; j < 4; ++j)
      centroid += corner(new_tets, s, j) / 4;
    Real best = -std::numeric_limits<Real>::infinity();
    for (std::size_t t = 0; t < old_slots; ++t) {
      if (!usable[t]) continue;
      const Real slack = kTolerance * bounds[t].diagonal().norm();
      if ((centroid.array() < bounds[t].min().array() - slack).any() ||
          (centroid.array() > bounds[t].max().array() + slack).any())
        continue;
      const Vec3 l = inverse[t] * (centroid - row3(rest, old_tets(static_cast<int>(t), 0)));
      const Real inside = std::min(Real(1) - l.sum(), l.minCoeff());
      if (inside > best) {
        best = inside;
        parents[k] = static_cast<int>(t);
      }
    }
    if (best < -kTolerance) parents[k] = -1;
  }
}

}  // namespace incise::sim::tools
