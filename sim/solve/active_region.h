#pragma once
// The active region of Paloc 2006 ("Selection of active tetrahedra"):
// only tets with a moving node are integrated; the rest of the body sleeps, frozen where it was.
//
//   active node     integrated; falls asleep after sleep_frames consecutive steps with its speed
//                   below sleep_speed and its net force below sleep_force (v set to 0, x kept)
//   sleeping node   frozen; wakes on wake(node) (a tool touched it) or when its net force
//                   (internal + external + gravity) exceeds wake_force > sleep_force (the gap is
//                   the hysteresis that keeps a node near the thresholds from flickering)
//   fixed node      never integrated (a Dirichlet node): asleep for good
//   active tet      a tet with an active node (as Paloc 2006 defines it)
//   frontier node   a sleeping node of an active tet: held, but pulled by its active neighbours,
//                   so its force is evaluated every step (that is how a wave wakes the next ring)
//   halo tet        a sleeping tet at a frontier node
//
// ActiveRegion is the bookkeeping only (no physics); ActiveExplicitStepper integrates with it.
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "sim/core/types.h"
#include "sim/mesh/tet_mesh.h"
#include "sim/models/model.h"

namespace incise::sim {

struct ActiveRegionSettings {
  Real sleep_speed = 0;  // [m/s], >= 0
  Real sleep_force = 0;  // [N], >= 0
  Real wake_force = 0;   // [N], > sleep_force
  int sleep_frames = 1;  // >= 1
};

// The live metrics of the last step.
struct ActiveRegionMetrics {
  int active_nodes = 0;
  int active_tets = 0;     // tets with an active node: the ones integrated
  int evaluated_tets = 0;  // tets of the sub-model the forces come from: at least the active and
                           // halo tets (ActiveExplicitStepper keeps a larger one while it is at
                           // least half used)
  int wakes = 0;           // nodes woken this step (force or wake())
  int sleeps = 0;          // nodes that fell asleep this step
  bool rebuilt = false;    // the sub-model's elements were updated this step
};

class ActiveRegion {
 public:
  //   tets       #tets by 4 node indices
  //   num_nodes  #nodes; every node starts asleep
  // Throws std::invalid_argument for settings out of range or an index outside [0, num_nodes).
  ActiveRegion(const Tets& tets, int num_nodes, const ActiveRegionSettings& settings);

  int num_nodes() const { return static_cast<int>(state_.size()); }
  const ActiveRegionSettings& settings() const { return settings_; }

  bool node_active(int node) const { return state_[node] == kActive; }
  bool node_fixed(int node) const { return state_[node] == kFixed; }
  // Wakes a sleeping node (no effect on an active or fixed one); true if it woke.
  bool wake(int node);
  // Puts a node to sleep for good (a Dirichlet node).
  void fix(int node);
  // Records one step of an active node: speed [m/s] after the step, net force [N] during it.
  // Returns true if the node fell asleep (the caller zeroes its velocity).
  bool observe(int node, Real speed, Real net_force);
  // True if a sleeping (not fixed) node with this net force [N] should wake.
  bool should_wake(Real net_force) const { return net_force > settings_.wake_force; }

  // True after a wake or sleep since the last update_sets().
  bool changed() const { return changed_; }
  // Recomputes the sets below from the node states: O(#tets). Allocates only when a set grows
  // past its previous capacity.
  void update_sets();

  // Valid after update_sets(), in increasing order:
  const std::vector<int>& active_nodes() const { return active_nodes_; }
  const std::vector<int>& active_tets() const { return active_tets_; }
  const std::vector<int>& evaluated_tets() const { return evaluated_tets_; }  // active + halo
  // The nodes of the evaluated tets whose every tet is evaluated: active and frontier nodes. The
  // force of such a node from the evaluated tets alone is its whole internal force.
  const std::vector<int>& complete_nodes() const { return complete_nodes_; }

 private:
  enum State : std::uint8_t { kAsleep, kActive, kFixed };

  Tets tets_;
  ActiveRegionSettings settings_;
  std::vector<State> state_;
  std::vector<int> calm_frames_;  // consecutive calm steps of an active node
  std::vector<std::uint8_t> mark_;
  bool changed_ = true;
  std::vector<int> active_nodes_, active_tets_, evaluated_tets_, complete_nodes_;
};

// Builds the model of a mesh (e.g. a lambda around make_model or a model's constructor).
using ModelFactory = std::function<std::unique_ptr<Model>(const TetMesh&)>;

// Symplectic Euler (as symplectic_euler_step) over the active region of a mesh. Forces come from a
// sub-model holding only the evaluated tets (active + halo): the factory's model of the whole mesh
// with the other elements dropped, updated through Model::update_elements by the tets that enter
// or leave the set (local in the FEM and mass-spring models). Why the halo: with it, every active
// and frontier node has all its tets and all its neighbours' tets in the sub-mesh, so for any model
// whose force on a node depends on the tets at the node and the masses of its neighbours (the FEM
// models, and the mass-spring model's eq. 7 damping c_ij, which uses m_j) the sub-model's force on
// those nodes equals the full model's exactly; the halo's outer nodes have wrong masses and forces,
// but they are frozen (v = 0, so the mass-spring dampers between them and the frontier, whose c_ij
// uses those wrong masses, exert no force) and their forces are not used. Integration uses the full
// model's masses. A deep sleeping node (not in the sub-mesh) keeps the internal force last
// evaluated on it (all its tets are frozen, so it does not change) for the wake test.
class ActiveExplicitStepper {
 public:
  //   mesh     rest, tets and labels; the state x, v the stepper starts from (nodes with a
  //            velocity awake, the others asleep)
  //   factory  builds the model of a sub-mesh; called once here on the whole mesh (masses and the
  //            initial internal forces) and again at every change of the active set
  //   fixed    nodes held where they are (never integrated)
  // Throws std::invalid_argument as ActiveRegion or for a fixed node out of range.
  ActiveExplicitStepper(const TetMesh& mesh, ModelFactory factory,
                        const ActiveRegionSettings& settings, const std::vector<int>& fixed = {});

  // One step: rebuild the sub-model if the set changed, wake the sleeping nodes whose net force
  // exceeds wake_force (then rebuild again), v <- v + dt (f / m + g), x <- x + dt v on the active
  // nodes, then put the calm ones to sleep.
  //   dt        time step [s], > 0
  //   gravity   [m/s^2]
  //   external  #nodes by 3 external forces [N]
  //   x, v      #nodes by 3 positions [m] and velocities [m/s], advanced in place (sleeping nodes
  //             untouched)
  // Allocates nothing unless the active set changed.
  void step(Real dt, const Vec3& gravity, const Points& external, Points& x, Points& v);

  ActiveRegion& region() { return region_; }
  const ActiveRegion& region() const { return region_; }
  const ActiveRegionMetrics& metrics() const { return metrics_; }
  const VecX& masses() const { return masses_; }  // full-mesh lumped masses [kg]
  // Internal force [N] last evaluated on each node (current for active and frontier nodes).
  const Points& internal_forces() const { return held_force_; }
  int rebuilds() const { return rebuilds_; }  // sub-model updates so far

 private:
  void update_region();
  void evaluate_forces(const Points& x, const Points& v);
  Real net_force(int node, const Vec3& gravity, const Points& external) const;

  TetMesh mesh_;  // the model's slot view: every tet of the mesh is a slot
  ModelFactory factory_;
  ActiveRegion region_;
  VecX masses_;
  Points held_force_;
  ActiveRegionMetrics metrics_;
  int rebuilds_ = 0;
  // The sub-model: the whole mesh's model whose elements outside the evaluated set are dropped
  // (Model::update_elements), so that a change of the set costs only the tets that enter or
  // leave it.
  std::unique_ptr<Model> sub_model_;
  std::vector<char> in_sub_;  // #tets, 1 for the tets the sub-model holds
  std::size_t sub_count_ = 0;
  std::vector<int> changed_;  // scratch: the slots of an update
  Points sub_f_;
};

}  // namespace incise::sim
