#pragma once

// A deformable body whose mesh is refined and decimated online (Paloc 2006, "Online
// remeshing of volumetric MSS"): the remesher's rest mesh, the simulation state over its vertex
// slots, and a model kept up to date by local updates (Model::update_elements) after every
// refinement or decimation call.
//
// Everything is indexed by slot: node i of the model and row i of x, v is vertex slot i of the
// RemeshMesh, element s of the model is tet slot s. Slots are freed and reused by the remesher;
// a dead vertex slot has no tets, hence zero mass, and is left where it is (inverse mass 0,
// velocity 0), so it never moves and never produces a NaN.

#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "sim/core/types.h"
#include "sim/mesh/tet_mesh.h"
#include "sim/models/model.h"
#include "sim/remesh/decimation.h"
#include "sim/remesh/refinement.h"
#include "sim/remesh/remesh_mesh.h"
#include "sim/remesh/size_field.h"
#include "sim/solve/symplectic_euler.h"

namespace incise::sim::remesh {

// Makes the body's model from a compact mesh (rest, x, v, tets, labels), e.g.
// [&](const TetMesh& m) { return make_model(scene, m); }.
using ModelFactory = std::function<std::unique_ptr<Model>(const TetMesh&)>;

// Which nodes are held fixed, by rest position; asked again for every inserted vertex, so that a
// vertex inserted on a clamped face is clamped too.
using FixedPredicate = std::function<bool(const Vec3& rest_point)>;

class AdaptiveBody {
 public:
  // The body on `mesh` (rest, tets, labels; x and v as the initial state if they have a row per
  // node, else x = rest and v = 0). The mesh is first made constrained Delaunay
  // (make_constrained_delaunay): its tets may change by flips (same nodes, same node numbering,
  // same volume), which full decimation then restores exactly. The model is made by
  // make_model on that mesh and then switched to the slot view.
  // Throws std::invalid_argument if a node belongs to no tet, x or v has the wrong size, or as
  // RemeshMesh and make_model.
  AdaptiveBody(const TetMesh& mesh, const ModelFactory& make_model);

  // Holds every current and future vertex whose rest point satisfies `is_fixed` (inverse mass 0,
  // velocity 0, position kept). An empty predicate frees all.
  void set_fixed(FixedPredicate is_fixed);

  // Refines the region of target_size (refinement.h). Each new vertex gets x and v interpolated
  // with its barycentric weights in the host tet (the rest tet that held it) from the host
  // nodes' current x and v: the deformed host tet's point, so an affinely deformed or moving
  // body keeps its state exactly and no existing node moves. The model is updated once, locally.
  RefinementStats refine(const SizeField& target_size, const RefinementSettings& settings);

  // Removes up to max_attempts inserted vertices whose rest point is outside `keep_refined`'s
  // region (Decimator: deferred ones are retried on later calls). A removed vertex's slot
  // becomes dead (mass 0); nothing is transferred, the remaining nodes keep x and v. The model is
  // updated once, locally.
  DecimationStats decimate(const SizeField& keep_refined, int max_attempts);

  // The smallest altitude a removal may leave [m] (Decimator::set_altitude_floor); 0 (the
  // default) for none. With refinement's floor_altitudes, give min(l_min, the start mesh's
  // smallest altitude) so that neither refinement nor decimation lowers the stable step below
  // its floor.
  void set_decimation_floor(Real min_altitude) { decimator_.set_altitude_floor(min_altitude); }

  // One symplectic Euler step (symplectic_euler.h) of all slots: internal forces of the model
  // plus `external` (#vertex slots by 3 [N], or 0 rows for none) and gravity [m/s^2]. Fixed and
  // dead slots do not move. Allocates only after the slot count grew.
  // Throws std::invalid_argument for dt <= 0 or a wrongly sized `external`.
  void step(Real dt, const Vec3& gravity, const Points& external);

  // The model's internal forces at the current x and v (#vertex slots by 3 [N]), into f.
  void internal_forces(Points& f);

  const Points& x() const { return view_.x; }  // #vertex slots by 3 positions [m]
  const Points& v() const { return view_.v; }  // #vertex slots by 3 velocities [m/s]
  // Writable state, for callers that drive nodes (x, v of dead slots are ignored).
  Points& x() { return view_.x; }
  Points& v() { return view_.v; }
  const VecX& inverse_masses() const { return inv_mass_; }  // #vertex slots, 0 = fixed or dead

  const Model& model() const { return *model_; }
  Model& model() { return *model_; }
  const RemeshMesh& mesh() const { return mesh_; }
  // The slot view the model is built on: rest per vertex slot, tets and labels per tet slot
  // (rows of dead slots hold stale values; see tet_alive).
  const TetMesh& slot_view() const { return view_; }
  const std::vector<char>& tet_alive() const { return alive_; }

  int num_tets() const { return mesh_.num_tets(); }
  int num_vertices() const { return mesh_.num_vertices(); }
  int num_vertex_slots() const { return mesh_.num_vertex_slots(); }

  // The alive part as a compact mesh (rest, x, v, tets, labels; for rendering, .vtu output or a
  // fresh model): nodes are the alive vertex slots in increasing order, vertex_ids (if given)
  // gets each node's slot.
  TetMesh to_tet_mesh(std::vector<int>* vertex_ids = nullptr) const;

 private:
  RemeshListener listener();
  void grow_vertex_slots();
  void record(const TetChanges& changes);
  void commit_changes();
  void update_inverse_masses();
  void update_inverse_mass(int vertex);

  RemeshMesh mesh_;
  TetMesh view_;
  std::vector<char> alive_;
  std::unique_ptr<Model> model_;
  Decimator decimator_;
  FixedPredicate is_fixed_;
  std::vector<char> fixed_;  // by vertex slot
  VecX inv_mass_;
  // The tet slots changed since the last model update, each once.
  std::vector<int> changed_;
  std::vector<char> changed_mark_;
  // The vertex slots of the changed tets (before and after), each once: only their masses can
  // have changed, so only their inverse masses are updated (a pass touches a few hundred of the
  // organ's thousands of vertices).
  std::vector<int> touched_vertices_;
  std::vector<char> touched_mark_;
  Points forces_;
  Prescribed none_;
};

}  // namespace incise::sim::remesh
