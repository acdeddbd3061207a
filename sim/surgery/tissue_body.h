#pragma once

// The deformable tissue of a surgical scene: a tet mesh whose state lives in mesh.x and
// mesh.v, its model, the held (attachment) nodes, and the boundary surface with the tree that
// tools collide with. Stepped by symplectic Euler; follows topology changes (cuts) with the
// model's local update where the element count did not shrink.
//
// One step, as SurgicalScene drives it:
//   begin_step()        refit the surface tree to x; internal = model forces(x, v); forces =
//                       internal (the tools' implicit push needs the other forces on a node);
//   (tools add theirs to forces() and read internal())
//   end_step(dt, g, p)  symplectic_euler_step with forces and the prescribed p.

#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "sim/collide/surface_bvh.h"
#include "sim/core/clone_ptr.h"
#include "sim/core/types.h"
#include "sim/cut/simplify_cut.h"
#include "sim/mesh/boundary_surface.h"
#include "sim/mesh/tet_mesh.h"
#include "sim/models/hybrid_condensed_model.h"
#include "sim/models/model.h"
#include "sim/solve/symplectic_euler.h"
#include "sim/surgery/bisection.h"

namespace incise::sim::surgery {

using ModelFactory = std::function<std::unique_ptr<Model>(const TetMesh&)>;

class TissueBody {
 public:
  // mesh: rest, x, v, tets and labels (x and v may be empty: the rest state). fixed: per node,
  // non-zero for a node held where it is (an attachment). The model is made once by make_model.
  // Throws std::invalid_argument for fixed of the wrong size, a mesh without tets, or as the
  // model and the surface tree do (an inverted tet, a face shared by three tets).
  //
  // dt, wave_speed (the fastest P-wave speed of the tissue [m/s]) and damping_time (the models'
  // Kelvin-Voigt time beta [s], stiffness-proportional damping; 0 for none) set the stability
  // guard. Symplectic Euler on a mode of frequency w with damping rate beta w^2 is stable for
  // w^2 (dt^2 + 2 beta dt) < 4. An element's own stable step is dt_e = kExplicitSafety * its
  // smallest altitude / wave_speed (stable_time_step's rule, for beta = 0); one that needs more
  // than that (a sliver a cut left) is softened: its stiffness (and stiffness-proportional
  // damping) times dt_e^2 / (dt^2 + 2 beta dt) (Model::soften_element), which lowers its w^2 by
  // as much. A model that cannot soften gets the element's nodes' masses scaled by the inverse
  // instead; heavy nodes, though, carry the inertia of thousands of others and distort the whole
  // body's motion (an inverted sliver around one stayed inverted for seconds). softened_elements()
  // and mass_scaled_nodes() say how many: metrics, the price of not blowing up (a softened sliver
  // is a tiny volume of softer tissue).
  //
  // far_field: per tet, non-zero for a tet of a condensed far field (empty: none). The model must
  // then be a HybridCondensedModel with these tets as its far field. They never change: refinement
  // leaves them alone, the sliver simplification never removes one of their nodes (pinned), and
  // cuts must stay out of them (SurgicalScene's guard); their condensed interior nodes are
  // recovered by recover_far_field.
  TissueBody(TetMesh mesh, const ModelFactory& make_model, std::vector<char> fixed, Real dt,
             Real wave_speed, Real damping_time, std::vector<char> far_field = {});

  TissueBody& operator=(const TissueBody&) = delete;
  // A deep copy (model and all), for a checkpoint of a scene: the scene's cutters, which keep
  // the mesh's address, are the scene's to rebind (ProgressiveCutter::rebind).
  std::unique_ptr<TissueBody> clone() const;

  // The mesh with the current state (x, v). Tools that change its topology (the scalpel) edit
  // it and then call topology_changed.
  TetMesh& mesh() { return mesh_; }
  const TetMesh& mesh() const { return mesh_; }
  const Model& model() const { return *model_; }
  const VecX& masses() const { return model_->masses(); }
  const VecX& inverse_masses() const { return inv_mass_; }  // 0 for held nodes
  bool is_fixed(int node) const { return fixed_[static_cast<std::size_t>(node)] != 0; }
  const collide::SurfaceBvh& bvh() const { return bvh_; }
  const BoundarySurface& surface() const { return surface_; }
  // The surface triangles as node indices (the tree's triangles).
  const Triangles& surface_faces() const { return faces_; }

  // Model forces at the state of begin_step [N], #nodes by 3.
  const Points& internal() const { return internal_; }
  // This step's total forces [N], #nodes by 3: internal() plus what tools add.
  Points& forces() { return forces_; }
  // What the tools added this step (forces() - internal()) [N]. Allocates.
  Points external() const { return forces_ - internal_; }

  // Mass-proportional damping [1/s] (SurgicalSceneSpec::ambient_damping), >= 0; 0 at first.
  // Applied implicitly: v / (1 + a dt) each step, so any value is stable.
  // Throws std::invalid_argument for a negative or non-finite value.
  void set_ambient_damping(Real per_second);
  Real ambient_damping() const { return ambient_damping_; }

  void begin_step();
  // Throws std::invalid_argument for dt <= 0 (as symplectic_euler_step).
  void end_step(Real dt, const Vec3& gravity, const Prescribed& prescribed);

  // The recovery of tissue left inside out (SurgicalScene::inverted_tets_pulled). Nothing in the
  // model brings back tissue that passed through tissue (there is no self-contact), and a
  // corotational element can rest at det F < 0. The inverted tets (det F <= 0, far field apart)
  // with no node within a segment's radius of it (`clear_of`: the tools) are joined into parts
  // by shared nodes; each part is fitted rigidly to its rest shape (mass-weighted centroid and
  // the rotation nearest to sum m (x - c)(X - C)^T), and its nodes are pulled `fraction` of the
  // way toward the fit, and stopped (v = 0). Held nodes stay, and so do the nodes `held` masks (a
  // grasper's, #nodes by 3; null: none). A part's rest shape is never
  // inverted, so repeated pulls undo the tangle; a fit per tet instead pulled neighbours against
  // each other and left a large tangle for good (docs/surgery_stability.md). Returns how many
  // tets pulled.
  struct Segment {
    Vec3 a, b;
    Real radius = 0;
  };
  int recover_inverted(Real fraction, std::span<const Segment> clear_of = {},
                       const AxisMask* held = nullptr);

  // After the mesh's topology changed: tets_before is the tet count before the change, changed
  // the slots (< #tets now) whose tet is new or replaced. The model is updated locally when
  // neither the tet nor the node count shrank, else rebuilt (Model::update_topology); new nodes
  // are held if their
  // rest point is a held node's (a cut's copies of an attachment stay attached); the surface and
  // its tree are rebuilt.
  void topology_changed(int tets_before, std::span<const int> changed);

  // Removes the slivers among the region's tets (slots) by checked edge collapses
  // (cut::simplify_cut_region: the inversion, topology and boundary checks of
  // Knee Arthroscopy VR, section VII.C) and compacts the mesh; held flags follow the nodes, and
  // the model, masses, surface and tree are rebuilt.
  // The report's tet_map and node_map say where each old slot and node went (-1: removed).
  cut::SimplifyReport simplify(std::span<const int> region, const cut::SimplifyOptions& options);

  // Refines around centre (rest [m]) by edge bisection (bisection.h) to edges of at most
  // edge_length, refusing any split that would make an element need softening (altitude_floor)
  // or a sliver. New nodes are held if both ends of their edge are; the model follows locally
  // (the mesh only grew), the masses, surface and tree are rebuilt. The splits are kept
  // (bisections()) so that coarsen can undo them.
  BisectionReport refine(const Vec3& centre, Real radius, Real edge_length, int max_splits);
  // Undoes the kept splits whose node's rest point keep() rejects (undo_bisections) and compacts
  // the mesh; the model is rebuilt (Model::update_topology), held flags follow the nodes.
  CoarsenReport coarsen(const std::function<bool(const Vec3& rest)>& keep);
  const std::vector<Bisection>& bisections() const { return bisections_; }
  // The smallest rest altitude an element may have without the stability guard softening it [m]:
  // wave_speed sqrt(dt^2 + 2 beta dt) / kExplicitSafety.
  Real altitude_floor() const;

  // The condensed far field: per tet slot (empty without one), and whether a node is one of its.
  const std::vector<char>& far_field() const { return far_; }
  bool far_field_node(int node) const {
    return !pinned_.empty() && pinned_[static_cast<std::size_t>(node)] != 0;
  }
  // Writes the far field's condensed interior nodes' positions (HybridCondensedModel::
  // recover_interior) into the mesh's x, for strain records and rendering; nothing without a
  // far field. They are not simulated: between calls they stay where the last call put them.
  void recover_far_field();

  // Counts of topology_changed calls: whether the model could follow locally.
  int local_updates() const { return local_updates_; }
  int full_updates() const { return full_updates_; }
  // The stability guard: elements softened (Model::soften_element) and the smallest stiffness
  // factor; nodes whose mass is scaled (for a model that cannot soften), and the largest factor.
  int softened_elements() const { return softened_elements_; }
  Real min_stiffness_factor() const { return min_stiffness_factor_; }
  int mass_scaled_nodes() const { return mass_scaled_nodes_; }
  Real max_mass_scale() const { return max_mass_scale_; }

 private:
  TissueBody(const TissueBody&) = default;  // through clone(), which fixes condensed_

  // The surface and its tree after a change: from scratch (changed == nullptr: a new mesh, a
  // compaction), or with the boundary tracker updated for the changed tet slots only (the mesh
  // grew: a cut frame, a refinement).
  void rebuild_surface(std::span<const int>* changed = nullptr);
  void update_inverse_masses();
  // After a compaction (node_map: old node -> new or -1): held flags and kept splits follow,
  // the model is rebuilt.
  void after_compaction(std::span<const int> node_map, std::span<const int> tet_map);
  // The far-field flags follow the tet and node counts (new tets and nodes are operational).
  void grow_far_field();

  TetMesh mesh_;
  ClonePtr<Model> model_;
  std::vector<char> fixed_;
  std::vector<std::array<Real, 3>> fixed_rest_;  // sorted rest points of held nodes
  VecX inv_mass_;
  BoundaryTracker boundary_;
  BoundarySurface surface_;
  Triangles faces_;
  collide::SurfaceBvh bvh_;
  Points internal_, forces_;
  std::vector<char> alive_;
  std::vector<Bisection> bisections_;
  std::vector<char> far_;     // per tet slot, or empty
  std::vector<char> pinned_;  // per node: a far-field tet's node, or empty
  HybridCondensedModel* condensed_ = nullptr;
  int local_updates_ = 0;
  int full_updates_ = 0;
  Real dt_;
  Real wave_speed_;
  Real damping_time_;
  Real ambient_damping_ = 0;
  std::vector<Real> mass_scale_;  // per node, >= 1
  int mass_scaled_nodes_ = 0;
  int softened_elements_ = 0;
  Real min_stiffness_factor_ = 1;
  Real max_mass_scale_ = 1;
  // recover_inverted's scratch, per node: its part (union-find), and each part's fit at its root.
  struct PartFit {
    Real mass = 0;
    Vec3 centre = Vec3::Zero();
    Vec3 rest_centre = Vec3::Zero();
    Mat3 covariance = Mat3::Zero();
    Mat3 rotation = Mat3::Identity();
  };
  std::vector<int> recover_part_;
  std::vector<PartFit> recover_fit_;
};

}  // namespace incise::sim::surgery
