#pragma once

// Per-element tissue damage over a session: strain over each tissue's threshold,
// cuts against the marked target, and tool contacts with structures that must not be touched.
// The tracker takes plain arrays (positions, crack faces, contact depths) and keeps its state as
// per-slot arrays; once sized it allocates nothing per step (record_strain, record_contacts).
// Cut events and topology updates allocate (they are events, not steps).
//
// Rules (docs/damage.md):
// - Strain: each step, every alive tet of a tracked label gets its largest principal Green
//   strain (damage_strain.h). Strictly above its label's threshold, the step's dt adds to the
//   tet's time over threshold and the tet is damaged for good; its peak is the largest strain it
//   reached. A label's damage index is its damaged rest volume over its alive rest volume. Labels
//   without a threshold are not tracked.
// - Topology changes (remeshing, cutting): update_elements(mesh, alive, changed, parents). A
//   changed slot's new tet inherits the damage state (peak, time over threshold, damaged flag) of
//   the tet in slot parents[k] BEFORE the update (-1: a fresh, undamaged tet); its volume and
//   threshold are its own. Pieces that split one damaged tet are all damaged, and their rest
//   volumes add up to the parent's, so a cut keeps the damaged volume. parents_by_rest_centroid
//   finds parents geometrically when the topology change does not report them.
// - Cuts: record_cut(rest, crack_faces) after update_elements. Crack faces come in pairs (one per
//   side, same rest triangle), so a face counts for half its rest area: the areas are those of
//   the cut surface. A face is on target when its rest centroid is within half_width of the
//   target surface (damage_target.h); distances are area-weighted. A crack face in a tet of a
//   protected label raises the never event.
// - Contacts: record_contacts(depths, dt) with the current penetration depth [m] of the tool into
//   each protected structure (<= 0: not touching; e.g. deepest_contact over its contacts). A
//   rising edge (touching now, not at the last call) is one collision event.

#include <span>
#include <vector>

#include "sim/collide/contact.h"
#include "sim/core/types.h"
#include "sim/mesh/tet_mesh.h"
#include "sim/tools/damage_metrics.h"
#include "sim/tools/damage_target.h"

namespace incise::sim::tools {

struct StrainThreshold {
  int label = 0;                  // tissue label (TetMesh::labels)
  Real max_principal_strain = 0;  // [-] Green strain above which the tissue is damaged, > 0
};

struct DamageSettings {
  std::vector<StrainThreshold> strain_thresholds;  // one per tracked label, labels distinct
  std::vector<int> protected_labels;               // tissue that must not be cut (never event)
  int protected_structures = 0;                    // contact channels record_contacts takes, >= 0
  MarkedTarget target;                             // the cut target; empty: no cut is on target
};

// What one cut event did (record_cut). Areas are rest areas of the cut surface (one side).
struct CutDamage {
  Real area = 0;                 // [m^2]
  Real area_inside_target = 0;   // [m^2]
  Real area_outside_target = 0;  // [m^2]
  Real mean_distance = 0;        // [m] area-weighted, 0 without a target
  Real max_distance = 0;         // [m] over crack face centroids, 0 without a target
  Real protected_area = 0;       // [m^2] in tets of protected labels
  bool never_event = false;      // protected_area > 0
};

// Per tracked label, in the order of DamageSettings::strain_thresholds.
struct LabelDamage {
  int label = 0;
  Real threshold = 0;       // [-]
  Real volume = 0;          // [m^3] alive rest volume of the label
  Real damaged_volume = 0;  // [m^3]
  Real damage_index = 0;    // [-] damaged_volume / volume (0 for a label with no volume)
};

// Per protected structure (contact channel), in the order of record_contacts' depths.
struct StructureContact {
  int collisions = 0;         // [count] rising edges
  Real contact_time = 0;      // [s]
  Real peak_penetration = 0;  // [m]
  bool touching = false;      // at the last record_contacts
};

class DamageTracker {
 public:
  // Every slot of mesh alive, or the slots with alive[s] != 0 (Model::update_elements' slot
  // view). Throws std::invalid_argument for a bad setting (threshold <= 0 or not finite, a label
  // listed twice, protected_structures < 0, an invalid target), labels of the wrong size, a node
  // index outside mesh.rest, or an alive tet not positively oriented at rest.
  DamageTracker(const TetMesh& mesh, DamageSettings settings);
  DamageTracker(const TetMesh& mesh, const std::vector<char>& alive, DamageSettings settings);

  // One step at positions x (#nodes by 3 [m]) lasting dt [s] (> 0, finite). Throws
  // std::invalid_argument, with the damage state unchanged (strain() may then hold part of the
  // failed step), if x has too few rows or an alive tracked tet's strain is not finite (x holds
  // NaN or infinity).
  void record_strain(const Points& x, Real dt);

  // The topology changed: the slot view as in Model::update_elements (mesh.tets rows are slots,
  // alive[s] != 0 holds a tet; the slot count may have grown), changed the slots whose tet
  // appeared, disappeared or was replaced, parents[k] the pre-update slot whose state changed[k]
  // inherits (-1: none). Throws std::invalid_argument, with the tracker unchanged, if parents and
  // changed differ in size, a slot or parent is out of range, alive is not #slots long, or a new
  // tet is bad (as in the constructor).
  void update_elements(const TetMesh& mesh, const std::vector<char>& alive,
                       std::span<const int> changed, std::span<const int> parents);

  // A cut event: crack_faces (#F by 3 node indices, CutReport::crack_faces) over rest positions
  // (#nodes by 3 [m]), after update_elements. Throws std::invalid_argument if a face's node is
  // out of range or no alive tet holds the face (update_elements not called?).
  CutDamage record_cut(const Points& rest, const Triangles& crack_faces);
  // The same with each face's tissue label given (labels[f] for crack face f), for faces that no
  // alive tet holds any more (e.g. a progressive cut's faces already split by the blade's
  // temporary pieces); no update_elements needed. Throws std::invalid_argument for labels of the
  // wrong size or a node outside rest.
  CutDamage record_cut(const Points& rest, const Triangles& crack_faces,
                       std::span<const int> labels);

  // The tool's current penetration [m] into each of the protected_structures structures (> 0
  // touching), over a step of dt [s]. Throws std::invalid_argument for a wrong count, a NaN depth
  // or a bad dt.
  void record_contacts(std::span<const Real> depths, Real dt);

  DamageMetrics metrics() const;
  std::span<const LabelDamage> label_damage() const { return labels_; }
  std::span<const StructureContact> structure_contacts() const { return structures_; }

  // Per slot (#slots): strain at the last step [-], peak strain [-], time over threshold [s],
  // damaged flag; 0 for dead or untracked slots.
  const VecX& strain() const { return strain_; }  // at the last record_strain
  const VecX& peak_strain() const { return peak_; }
  const VecX& time_over_threshold() const { return time_over_; }
  const std::vector<char>& damaged() const { return damaged_; }
  int num_slots() const { return static_cast<int>(tets_.rows()); }

 private:
  // Per-slot geometry of slot s from mesh; throws for a bad tet.
  void set_slot(const TetMesh& mesh, int s);
  void recompute_volumes();

  DamageSettings settings_;
  Tets tets_;                       // #slots by 4, copied from the mesh
  std::vector<char> alive_;         // #slots
  std::vector<int> label_;          // #slots tissue label
  std::vector<int> label_index_;    // #slots: index into labels_, -1 untracked
  std::vector<char> tracked_;       // #slots: alive with a tracked label (the strain is taken)
  std::vector<Mat3> rest_inverse_;  // #slots Dm^-1
  VecX rest_volume_;                // #slots [m^3]
  VecX strain_;                     // #slots [-] at the last step
  VecX peak_;                       // #slots [-]
  VecX time_over_;                  // #slots [s]
  std::vector<char> damaged_;       // #slots
  int min_rows_ = 0;                // rows x must have: 1 + the largest alive node index

  std::vector<LabelDamage> labels_;
  std::vector<StructureContact> structures_;
  DamageMetrics totals_;        // running session values (the strain volumes come from labels_)
  Real weighted_distance_ = 0;  // [m^3] sum of area * distance over all crack faces
};

// The deepest penetration [m] among contacts (0 if none), counting only contacts whose triangle
// t has triangle_is_protected[t] != 0, or all of them when triangle_is_protected is empty. For
// record_contacts: e.g. a RigidBody's contacts, or the tissue surface's contacts with the faces
// of protected labels flagged. Throws std::invalid_argument for a triangle index outside a
// non-empty triangle_is_protected.
Real deepest_contact(std::span<const collide::Contact> contacts,
                     std::span<const char> triangle_is_protected = {});

// For update_elements when a topology change does not report where its new tets come from:
// parents[k] = the slot of old_tets (alive in old_alive) that holds the rest centroid of
// new_tets.row(changed[k]) (the one it is deepest inside, within a tolerance), or -1. Right for
// cutting and refinement, where each new tet lies inside one old tet; for decimation, the old tet
// under the new tet's centroid. rest must hold every node of both. Cost O(#changed x #old slots):
// an event-time helper, not a per-step one.
void parents_by_rest_centroid(const Points& rest, const Tets& old_tets,
                              const std::vector<char>& old_alive, const Tets& new_tets,
                              std::span<const int> changed, std::vector<int>& parents);

}  // namespace incise::sim::tools
