#include "sim/surgery/surgical_scene.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>
#include <utility>

#include "sim/cut/material_map.h"
#include "sim/models/hybrid_condensed_model.h"

namespace incise::sim::surgery {

std::string_view to_string(ToolKind kind) {
  switch (kind) {
    case ToolKind::probe:
      return "probe";
    case ToolKind::grasper:
      return "grasper";
    case ToolKind::scalpel:
      return "scalpel";
    case ToolKind::scope:
      return "scope";
  }
  return "?";
}

std::string_view to_string(EventKind kind) {
  switch (kind) {
    case EventKind::grab:
      return "grab";
    case EventKind::release:
      return "release";
    case EventKind::cut:
      return "cut";
    case EventKind::collision:
      return "collision";
    case EventKind::never_event:
      return "never_event";
  }
  return "?";
}

struct SurgicalScene::Tool {
  ToolSpec spec;
  bool has_input = false;
  ToolInput input;
  Vec3 tip = Vec3::Zero();
  Mat3 rotation = Mat3::Identity();
  Vec3 direction = Vec3::UnitZ();
  std::optional<tools::Probe> probe;  // probe and scope, made at the first input
  std::optional<tools::Grasper> grasper;
  std::unique_ptr<cut::ProgressiveCutter> cutter;
  bool stroke = false;            // the scalpel's blade is in the tissue
  std::vector<int> stroke_slots;  // committed slots the open stroke's complete cuts changed
  tools::LocalForceModel bone;    // this step's bone contacts, on the tool at its tip
  bool touching_bone = false;
  Vec3 hand_force = Vec3::Zero();  // grasper: the tissue's pull on the hand
};

namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("surgical scene: " + what);
}

std::string field(std::size_t k, const char* name) {
  return "tools[" + std::to_string(k) + "]." + name;
}

void validate(const SurgicalSceneSpec& spec) {
  require(spec.dt > 0 && std::isfinite(spec.dt), "dt must be > 0");
  require(spec.gravity.allFinite(), "gravity must be finite");
  require(spec.bone_stiffness > 0 && std::isfinite(spec.bone_stiffness),
          "bone_stiffness must be > 0");
  require(spec.wave_speed > 0 && std::isfinite(spec.wave_speed), "wave_speed must be > 0");
  require(spec.damping_time >= 0 && std::isfinite(spec.damping_time), "damping_time must be >= 0");
  require(spec.ambient_damping >= 0 && std::isfinite(spec.ambient_damping),
          "ambient_damping must be >= 0");
  require(spec.cut_every >= 1, "cut_every must be >= 1");
  require(spec.damage_every >= 1, "damage_every must be >= 1");
  const AdaptivitySpec& a = spec.adaptivity;
  require(a.edge_length > 0 && std::isfinite(a.edge_length), "adaptivity.edge_length must be > 0");
  require(a.radius > 0 && std::isfinite(a.radius), "adaptivity.radius must be > 0");
  require(a.coarsen_after >= 0 && std::isfinite(a.coarsen_after),
          "adaptivity.coarsen_after must be >= 0");
  require(a.max_splits >= 1, "adaptivity.max_splits must be >= 1");
  if (spec.far_field.enabled) {
    require(spec.far_field.centre.allFinite(), "far_field.centre must be finite");
    require(spec.far_field.radius > 0 && std::isfinite(spec.far_field.radius),
            "far_field.radius must be > 0");
  }
  for (std::size_t k = 0; k < spec.tools.size(); ++k) {
    const ToolSpec& t = spec.tools[k];
    require(t.device >= 0, field(k, "device") + " must be >= 0");
    require(t.shaft_length > 0 && t.shaft_radius > 0,
            field(k, "shaft") + " length and radius must be > 0");
    require(t.max_jaw_angle > 0 && t.max_jaw_angle < std::numbers::pi,
            field(k, "max_jaw_angle") + " must be in (0, pi)");
    require(t.blade_length > 0, field(k, "blade_length") + " must be > 0");
    require(t.view_angle_degrees >= 0 && t.view_angle_degrees < 90,
            field(k, "view_angle_degrees") + " must be in [0, 90)");
    require(t.field_of_view_degrees > 0 && t.field_of_view_degrees < 180,
            field(k, "field_of_view_degrees") + " must be in (0, 180)");
  }
}

// The deepest contact of a list, or nullptr.
const collide::Contact* deepest(const std::vector<collide::Contact>& contacts) {
  const collide::Contact* best = nullptr;
  for (const collide::Contact& c : contacts) {
    if (best == nullptr || c.depth > best->depth) best = &c;
  }
  return best;
}

// The far field's tets: no node within the region (rest).
std::vector<char> far_field_tets(const TetMesh& mesh, const FarFieldSpec& region) {
  std::vector<char> far(static_cast<std::size_t>(mesh.num_tets()), 1);
  for (int t = 0; t < mesh.num_tets(); ++t) {
    for (int k = 0; k < 4; ++k) {
      if ((row3(mesh.rest, mesh.tets(t, k)) - region.centre).norm() < region.radius) {
        far[static_cast<std::size_t>(t)] = 0;
      }
    }
  }
  return far;
}

// Renumbers the nodes so that the far field's come first, in their order, then the others: a
// compaction (sliver collapses, coarsening) removes operational nodes only and keeps the order,
// so the far field's tets keep their node numbers, which the condensed model holds them by.
void far_field_nodes_first(TetMesh& mesh, std::vector<char>& fixed, const std::vector<char>& far) {
  const int n = mesh.num_nodes();
  std::vector<char> in_far(static_cast<std::size_t>(n), 0);
  for (int t = 0; t < mesh.num_tets(); ++t) {
    if (far[static_cast<std::size_t>(t)] == 0) continue;
    for (int k = 0; k < 4; ++k)
      in_far[static_cast<std::size_t>(mesh.tets(t, k))] = 1;
  }
  std::vector<int> order;  // new -> old
  for (int pass = 1; pass >= 0; --pass) {
    for (int i = 0; i < n; ++i) {
      if (in_far[static_cast<std::size_t>(i)] == pass) order.push_back(i);
    }
  }
  std::vector<int> new_of(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k)
    new_of[static_cast<std::size_t>(order[static_cast<std::size_t>(k)])] = k;
  const auto permute = [&](Points& p) {
    if (p.rows() != n) return;
    Points q(n, 3);
    for (int k = 0; k < n; ++k)
      q.row(k) = p.row(order[static_cast<std::size_t>(k)]);
    p = std::move(q);
  };
  permute(mesh.rest);
  permute(mesh.x);
  permute(mesh.v);
  for (int t = 0; t < mesh.num_tets(); ++t) {
    for (int k = 0; k < 4; ++k)
      mesh.tets(t, k) = new_of[static_cast<std::size_t>(mesh.tets(t, k))];
  }
  std::vector<char> f(fixed.size(), 0);
  for (int k = 0; k < n && static_cast<std::size_t>(k) < fixed.size(); ++k)
    f[static_cast<std::size_t>(k)] =
        fixed[static_cast<std::size_t>(order[static_cast<std::size_t>(k)])];
  fixed = std::move(f);
}

}  // namespace

SurgicalScene::SurgicalScene(SurgicalSceneSpec spec) : spec_(std::move(spec)) {
  validate(spec_);
  std::vector<char> far;
  ModelFactory model = spec_.model;
  if (spec_.far_field.enabled) {
    far = far_field_tets(spec_.tissue, spec_.far_field);
    const auto far_count = std::count(far.begin(), far.end(), 1);
    require(far_count > 0, "far_field: no tet lies outside the region (radius too large)");
    require(far_count < static_cast<long>(far.size()), "far_field: no tet lies inside the region");
    require(spec_.fixed.size() == static_cast<std::size_t>(spec_.tissue.num_nodes()),
            "fixed must have one entry per tissue node");
    far_field_nodes_first(spec_.tissue, spec_.fixed, far);
    // The guard: the longest edge of the operational tets that share a node with the far field.
    // A tet the blade passes through at a point more than that inside the region cannot hold a
    // far-field node (every one is outside the region), so neither it nor a tet sharing one of
    // its edges or faces (which holds that edge's or face's nodes) is a far-field tet: the cut
    // leaves the far field alone. The region less the guard is a ball, so the blade's ends
    // suffice.
    std::vector<char> far_node(static_cast<std::size_t>(spec_.tissue.num_nodes()), 0);
    for (int t = 0; t < spec_.tissue.num_tets(); ++t) {
      if (far[static_cast<std::size_t>(t)] == 0) continue;
      for (int k = 0; k < 4; ++k)
        far_node[static_cast<std::size_t>(spec_.tissue.tets(t, k))] = 1;
    }
    Real longest = 0;
    for (int t = 0; t < spec_.tissue.num_tets(); ++t) {
      bool interface = false;
      for (int k = 0; k < 4; ++k)
        interface = interface || far_node[static_cast<std::size_t>(spec_.tissue.tets(t, k))] != 0;
      if (far[static_cast<std::size_t>(t)] != 0 || !interface) continue;
      for (int i = 0; i < 4; ++i) {
        for (int j = i + 1; j < 4; ++j) {
          longest = std::max(longest, (row3(spec_.tissue.rest, spec_.tissue.tets(t, i)) -
                                       row3(spec_.tissue.rest, spec_.tissue.tets(t, j)))
                                          .norm());
        }
      }
    }
    far_guard_ = 1.1 * longest;  // a margin for the blade's material map
    const ModelFactory operational = spec_.model;
    require(static_cast<bool>(operational), "model: no factory");
    model = [operational, far, materials = spec_.far_field.materials](const TetMesh& mesh) {
      std::vector<char> flags(far.size());
      for (std::size_t t = 0; t < far.size(); ++t)
        flags[t] = far[t] != 0 ? 0 : 1;
      return std::make_unique<HybridCondensedModel>(
          mesh, flags, materials,
          [operational](const TetMesh& m, const std::vector<ElementMaterial>&) {
            return operational(m);
          });
    };
  }
  tissue_ = std::make_unique<TissueBody>(spec_.tissue, model, spec_.fixed, spec_.dt,
                                         spec_.wave_speed, spec_.damping_time, far);
  tissue_->set_ambient_damping(spec_.ambient_damping);
  for (std::size_t b = 0; b < spec_.bones.size(); ++b) {
    try {
      bones_.emplace_back(spec_.bones[b].vertices, spec_.bones[b].triangles);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("surgical scene: bones[" + std::to_string(b) + "] (" +
                                  spec_.bones[b].name + "): " + e.what());
    }
  }
  bone_depths_.assign(bones_.size(), 0);
  bone_touching_.assign(bones_.size(), 0);
  for (const ToolSpec& t : spec_.tools) {
    Tool tool;
    tool.spec = t;
    tool.spec.probe.contact.time_step = spec_.dt;
    if (t.kind == ToolKind::scope) tool.spec.probe.radius = t.shaft_radius;
    if (t.kind == ToolKind::grasper) tool.grasper.emplace(t.grasp);
    tools_.push_back(std::move(tool));
  }
  tools::DamageSettings damage = spec_.damage;
  damage.protected_structures = static_cast<int>(bones_.size());
  damage_ = std::make_unique<tools::DamageTracker>(tissue_->mesh(), damage);
  damage_alive_.assign(static_cast<std::size_t>(tissue_->mesh().num_tets()), 1);
  const TetMesh& mesh = tissue_->mesh();
  prescribed_.mask = AxisMask::Zero(mesh.num_nodes(), 3);
  prescribed_.position = Points::Zero(mesh.num_nodes(), 3);
  surface_nodes_ = tissue_->surface().nodes;
}

SurgicalScene::~SurgicalScene() = default;

int SurgicalScene::num_tools() const {
  return static_cast<int>(tools_.size());
}

void SurgicalScene::event(EventKind kind, int tool, std::string detail) {
  events_.push_back({kind, tool, time_ + spec_.dt, std::move(detail)});
}

std::vector<SceneEvent> SurgicalScene::take_events() {
  std::vector<SceneEvent> out;
  out.swap(events_);
  return out;
}

void SurgicalScene::step(std::span<const ToolInput> inputs) {
  for (const ToolInput& in : inputs) {
    if (!in.tip.allFinite() || !in.orientation.coeffs().allFinite() || !std::isfinite(in.jaw)) {
      throw std::invalid_argument("surgical scene: a tool input is not finite");
    }
  }
  for (Tool& tool : tools_) {
    const auto d = static_cast<std::size_t>(tool.spec.device);
    if (d >= inputs.size()) continue;
    tool.has_input = true;
    tool.input = inputs[d];
    tool.rotation = tool.input.orientation.normalized().toRotationMatrix();
    tool.direction = tool.rotation.col(2);
    tool.tip = tool.input.tip;
  }
  for (std::size_t k = 0; k < tools_.size(); ++k) {
    if (tools_[k].grasper && tools_[k].has_input) set_jaws(tools_[k], static_cast<int>(k));
  }
  if (spec_.adaptivity.enabled) adapt();
  // Cuts first, so that this step's forces are those of the new topology.
  if (steps_ % spec_.cut_every == 0) {
    for (std::size_t k = 0; k < tools_.size(); ++k) {
      if (tools_[k].spec.kind == ToolKind::scalpel && tools_[k].has_input) {
        cut(tools_[k], static_cast<int>(k));
      }
    }
  }
  tissue_->begin_step();
  TetMesh& mesh = tissue_->mesh();
  for (const int row : prescribed_rows_)
    prescribed_.mask.row(row).setZero();
  prescribed_rows_.clear();
  std::fill(bone_depths_.begin(), bone_depths_.end(), 0);
  for (std::size_t k = 0; k < tools_.size(); ++k) {
    Tool& tool = tools_[k];
    if (!tool.has_input) continue;
    switch (tool.spec.kind) {
      case ToolKind::probe:
      case ToolKind::scope:
        if (!tool.probe) tool.probe.emplace(tool.spec.probe, tool.tip);
        tool.probe->step(tool.tip, tissue_->bvh(), mesh.x, mesh.v, tissue_->masses(),
                         tissue_->forces(), &tissue_->inverse_masses());
        break;
      case ToolKind::grasper:
        grasp(tool, static_cast<int>(k));
        break;
      case ToolKind::scalpel:
        break;
    }
    bones(tool, static_cast<int>(k));
  }
  tissue_->end_step(spec_.dt, spec_.gravity, prescribed_);
  // Bone contacts: a rising edge per bone is a collision with a protected structure.
  for (std::size_t b = 0; b < bones_.size(); ++b) {
    const bool touching = bone_depths_[b] > 0;
    if (touching && bone_touching_[b] == 0) {
      event(EventKind::collision, -1, spec_.bones[b].name);
    }
    bone_touching_[b] = touching ? 1 : 0;
  }
  damage_->record_contacts(bone_depths_, spec_.dt);
  strain_time_ += spec_.dt;
  ++steps_;
  time_ += spec_.dt;
  if (steps_ % spec_.damage_every == 0 && state_finite()) {
    tissue_->recover_far_field();  // the far field's interior, for its strains
    try {
      damage_->record_strain(mesh.x, strain_time_);
    } catch (const std::invalid_argument&) {
      ++strain_records_skipped_;  // a strain overflowed: the state is running away
    }
    strain_time_ = 0;
  }
}

void SurgicalScene::set_jaws(Tool& tool, int index) {
  tools::JawPose pose;
  pose.pivot = tool.tip;
  pose.direction = tool.direction;
  pose.opening_normal = tool.rotation.col(0);
  pose.opening_angle = std::clamp(tool.input.jaw, 0.0, 1.0) * tool.spec.max_jaw_angle;
  if (const auto released = tool.grasper->set_jaws(pose)) {
    char text[64];
    std::snprintf(text, sizeof text, "%s, %d vertices",
                  std::string(to_string(released->reason)).c_str(), released->released_vertices);
    event(EventKind::release, index, text);
  }
}

void SurgicalScene::grasp(Tool& tool, int index) {
  tools::Grasper& grasper = *tool.grasper;
  TetMesh& mesh = tissue_->mesh();
  if (grasper.phase() == tools::GraspPhase::closing) {
    // Only committed nodes: a scalpel's temporary nodes are renumbered every cut frame.
    const int stable = stable_nodes();
    std::vector<int> candidates;
    for (const int v : surface_nodes_) {
      if (v < stable) candidates.push_back(v);
    }
    const int grabbed = grasper.grab(mesh.rest, mesh.x, tissue_->inverse_masses(), candidates);
    if (grabbed > 0) event(EventKind::grab, index, std::to_string(grabbed) + " vertices");
  }
  if (const auto released = grasper.measure(tissue_->internal())) {
    char text[64];
    std::snprintf(text, sizeof text, "%s at %.3f N",
                  std::string(to_string(released->reason)).c_str(), released->pull.norm());
    event(EventKind::release, index, text);
  }
  tool.hand_force = -grasper.pull();
  if (grasper.phase() == tools::GraspPhase::holding) {
    grasper.prescribe(prescribed_);
    for (const int v : grasper.grabbed())
      prescribed_rows_.push_back(v);
  } else {
    tool.hand_force.setZero();
  }
}

void SurgicalScene::bones(Tool& tool, int /*index*/) {
  tool.bone = {};
  tool.bone.reference_position = tool.tip;
  tool.touching_bone = false;
  if (bones_.empty()) return;
  const Real tip_radius =
      tool.spec.kind == ToolKind::probe ? tool.spec.probe.radius : tool.spec.shaft_radius;
  const collide::Sphere tip{tool.tip, tip_radius};
  const collide::Capsule shaft{tool.tip - tool.spec.shaft_length * tool.direction, tool.tip,
                               tool.spec.shaft_radius};
  std::vector<collide::Contact> contacts;
  for (std::size_t b = 0; b < bones_.size(); ++b) {
    for (int shape = 0; shape < 2; ++shape) {
      contacts.clear();
      if (shape == 0) {
        bones_[b].contacts(tip, contacts);
      } else {
        bones_[b].contacts(shaft, contacts);
      }
      const collide::Contact* c = deepest(contacts);
      if (c == nullptr || !(c->depth > 0)) continue;
      // A penalty on the tool along the bone's normal; K = k n n^T (PSD).
      tool.bone.force += spec_.bone_stiffness * c->depth * c->normal;
      tool.bone.stiffness += spec_.bone_stiffness * c->normal * c->normal.transpose();
      tool.touching_bone = true;
      bone_depths_[b] = std::max(bone_depths_[b], c->depth);
    }
  }
}

void SurgicalScene::cut(Tool& tool, int index) {
  TetMesh& mesh = tissue_->mesh();
  const Vec3 a = tool.tip;
  const Vec3 b = tool.tip - tool.spec.blade_length * tool.direction;
  std::vector<int> near;
  tissue_->bvh().overlapping_triangles(mesh.x, collide::Capsule{a, b, 1e-4}, near);
  if (!tool.stroke && near.empty()) return;
  // A blade reaching the condensed far field (which cannot change) ends its stroke there.
  const bool outside = far_guard_ > 0 && blade_outside_region(a, b);
  if (outside) ++cuts_outside_region_;
  if (!tool.stroke && outside) return;
  // The blade cuts the material it passes through: the cutter maps it into the rest
  // configuration through the tet its tip is in, so tissue moving under the blade is not cut
  // again (progressive_cutter.h). Where that tet is squashed or inverted (a violent push has
  // tangled the tissue there) the blade has no place in the material: the cut waits until the
  // tissue has recovered, and says so (cuts_refused).
  if (!tool.cutter) {
    tool.cutter = std::make_unique<cut::ProgressiveCutter>(mesh, cut::CutOptions{}, 0,
                                                           cut::BladeSpace::material);
  }
  int tets_before = mesh.num_tets();
  std::vector<int> changed;
  Triangles committed;
  std::vector<int> labels;
  if (outside) {
    tool.stroke = false;
  } else {
    const cut::FrameReport& report = tool.cutter->update(a, b);
    tets_before = report.tets_before;
    changed = report.changed_tets;
    committed = report.committed_crack_face_nodes;
    labels = report.committed_crack_face_labels;
    if (report.blade_unmapped && !near.empty()) ++cuts_refused_;
    tool.stroke = !near.empty() || report.front_tets > 0;
    if (report.committed_new_tets > 0 || report.committed_crack_faces > 0) {
      for (const int s : changed) {
        if (s < tool.cutter->committed_tets()) tool.stroke_slots.push_back(s);
      }
    }
  }
  if (!tool.stroke) {
    // The blade has left the tissue: its temporary pieces go, and the tets along the path of its
    // tip keep the crack the stroke left in them (a cut shallower than the tets opens too).
    const int before = mesh.num_tets();
    const cut::FrameReport& end = tool.cutter->end_stroke(true);
    changed.insert(changed.end(), end.changed_tets.begin(), end.changed_tets.end());
    std::sort(changed.begin(), changed.end());
    changed.erase(std::unique(changed.begin(), changed.end()), changed.end());
    changed.erase(std::lower_bound(changed.begin(), changed.end(), mesh.num_tets()), changed.end());
    if (end.committed_crack_faces > 0) {
      const Eigen::Index rows = committed.rows();
      committed.conservativeResize(rows + end.committed_crack_face_nodes.rows(), 3);
      committed.bottomRows(end.committed_crack_face_nodes.rows()) = end.committed_crack_face_nodes;
      labels.insert(labels.end(), end.committed_crack_face_labels.begin(),
                    end.committed_crack_face_labels.end());
      tool.stroke_slots.insert(tool.stroke_slots.end(), end.changed_tets.begin(),
                               end.changed_tets.end());
    }
    if (mesh.num_tets() != before || !changed.empty()) after_topology_change(tets_before, changed);
  } else if (!changed.empty() || mesh.num_tets() != tets_before) {
    after_topology_change(tets_before, changed);
  }
  if (committed.rows() > 0) {
    // Recorded with the labels the cutter found: some of these faces are already split by the
    // blade's temporary pieces, so no tet holds them now.
    const tools::CutDamage cut = damage_->record_cut(mesh.rest, committed, labels);
    char text[96];
    std::snprintf(text, sizeof text, "%.1f mm^2, %.1f mm^2 off target", 1e6 * cut.area,
                  1e6 * cut.area_outside_target);
    event(EventKind::cut, index, text);
    if (cut.never_event) event(EventKind::never_event, index, "a protected tissue was cut");
  }
  if (!tool.stroke) simplify_after_stroke(tool);
}

bool SurgicalScene::blade_outside_region(const Vec3& a, const Vec3& b) const {
  const TetMesh& mesh = tissue_->mesh();
  const FarFieldSpec& region = spec_.far_field;
  for (const Vec3& p : {a, b}) {
    // Where the blade's end is in the material; where it cannot be mapped (in the air beyond
    // reach), its position stands for it.
    const auto map = cut::material_map_at(mesh, p, 2 * far_guard_);
    const Vec3 rest = map ? map->rest_of(p) : p;
    if ((rest - region.centre).norm() > region.radius - far_guard_) return true;
  }
  return false;
}

void SurgicalScene::simplify_after_stroke(Tool& tool) {
  std::vector<int> region;
  region.swap(tool.stroke_slots);
  if (region.empty()) return;
  // Node and slot numbers change: wait while another stroke is open or a grasper holds (their
  // indices would go stale); the slivers stay until the next stroke ends.
  for (const Tool& other : tools_) {
    if (other.stroke) return;
    if (other.grasper && (other.grasper->phase() == tools::GraspPhase::holding ||
                          other.grasper->phase() == tools::GraspPhase::closing)) {
      return;
    }
  }
  std::sort(region.begin(), region.end());
  region.erase(std::unique(region.begin(), region.end()), region.end());
  region.erase(std::lower_bound(region.begin(), region.end(), tissue_->mesh().num_tets()),
               region.end());
  const int slots_before = std::max(damage_->num_slots(), tissue_->mesh().num_tets());
  const cut::SimplifyReport report = tissue_->simplify(region, spec_.simplify);
  collapses_ += report.collapses;
  if (report.collapses == 0) return;
  after_compaction(report.tet_map, slots_before);
}

void SurgicalScene::after_compaction(std::span<const int> tet_map, int slots_before) {
  // Every cutter's numbering is stale (none has an open stroke): a new one is made at the next
  // stroke.
  for (Tool& t : tools_) {
    t.cutter.reset();
    std::vector<int> slots;
    for (const int s : t.stroke_slots) {
      const int to =
          s < static_cast<int>(tet_map.size()) ? tet_map[static_cast<std::size_t>(s)] : -1;
      if (to >= 0) slots.push_back(to);
    }
    t.stroke_slots = std::move(slots);
  }
  // The damage tracker's slots follow the compaction: a kept tet inherits its old slot's state.
  const TetMesh& mesh = tissue_->mesh();
  const int slots = std::max(slots_before, mesh.num_tets());
  TetMesh view;
  view.rest = mesh.rest;
  view.tets.resize(slots, 4);
  view.labels.resize(slots);
  damage_alive_.assign(static_cast<std::size_t>(slots), 0);
  std::vector<int> all(static_cast<std::size_t>(slots));
  std::vector<int> parents(static_cast<std::size_t>(slots), -1);
  for (int s = 0; s < slots; ++s) {
    all[static_cast<std::size_t>(s)] = s;
    const bool alive = s < mesh.num_tets();
    view.tets.row(s) = mesh.tets.row(alive ? s : 0);
    view.labels(s) = mesh.labels(alive ? s : 0);
    damage_alive_[static_cast<std::size_t>(s)] = alive ? 1 : 0;
  }
  for (std::size_t old = 0; old < tet_map.size(); ++old) {
    const int to = tet_map[old];
    if (to >= 0 && static_cast<int>(old) < damage_->num_slots()) {
      parents[static_cast<std::size_t>(to)] = static_cast<int>(old);
    }
  }
  damage_->update_elements(view, damage_alive_, all, parents);
  follow_node_count();
}

void SurgicalScene::update_damage(int tets_before, std::span<const int> changed,
                                  std::span<const int> parents) {
  const TetMesh& mesh = tissue_->mesh();
  // The damage tracker's slots never shrink: slots beyond the mesh's tets are dead.
  const int slots = std::max(damage_->num_slots(), mesh.num_tets());
  TetMesh view;
  view.rest = mesh.rest;
  view.tets.resize(slots, 4);
  view.labels.resize(slots);
  damage_alive_.assign(static_cast<std::size_t>(slots), 0);
  std::vector<std::pair<int, int>> all;  // slot, parent
  for (std::size_t k = 0; k < changed.size(); ++k) {
    all.emplace_back(changed[k], parents.empty() ? -1 : parents[k]);
  }
  for (int s = 0; s < slots; ++s) {
    if (s < mesh.num_tets()) {
      view.tets.row(s) = mesh.tets.row(s);
      view.labels(s) = mesh.labels(s);
      damage_alive_[static_cast<std::size_t>(s)] = 1;
    } else {
      view.tets.row(s) = mesh.tets.row(0);  // dead: any valid row
      view.labels(s) = mesh.labels(0);
      if (s < tets_before || s < damage_->num_slots()) all.emplace_back(s, -1);
    }
  }
  std::sort(all.begin(), all.end());
  all.erase(std::unique(all.begin(), all.end(),
                        [](const auto& p, const auto& q) { return p.first == q.first; }),
            all.end());
  std::vector<int> slots_changed, slot_parents;
  for (const auto& [slot, parent] : all) {
    slots_changed.push_back(slot);
    slot_parents.push_back(parent < damage_->num_slots() ? parent : -1);
  }
  damage_->update_elements(view, damage_alive_, slots_changed, slot_parents);
}

void SurgicalScene::adapt() {
  const AdaptivitySpec& a = spec_.adaptivity;
  for (const Tool& t : tools_) {
    if (t.stroke) return;  // the cutter's temporary nodes would go stale
  }
  const TetMesh& mesh = tissue_->mesh();
  bool hold_off = false;  // no coarsening now: a grasper holds or closes, a probe touches
  for (std::size_t k = 0; k < tools_.size(); ++k) {
    Tool& tool = tools_[k];
    if (!tool.has_input) continue;
    const int index = static_cast<int>(k);
    if (tool.spec.kind == ToolKind::probe && tool.probe) {
      // Where the probe touched at the last step: refined once, kept while it touches nearby.
      const tools::ContactRegion touch = tool.probe->contact_region(mesh.rest);
      if (!touch.touching) continue;
      bool known = false;
      for (Region& r : regions_) {
        if (r.tool == index && (r.centre - touch.centre).norm() < 0.5 * r.radius) {
          r.last_used = time_;
          known = true;
        }
      }
      if (!known) refine(index, touch.centre, std::max(a.radius, touch.radius + a.edge_length));
    } else if (tool.grasper) {
      const tools::GraspPhase phase = tool.grasper->phase();
      if (phase == tools::GraspPhase::closing) {
        hold_off = true;
        std::vector<int> candidates;
        const int stable = stable_nodes();
        for (const int v : surface_nodes_) {
          if (v < stable) candidates.push_back(v);
        }
        if (const auto request = tool.grasper->refine_request(
                mesh.rest, mesh.x, tissue_->inverse_masses(), candidates)) {
          refine(index, request->centre, request->radius + a.edge_length);
        }
      } else if (phase == tools::GraspPhase::holding) {
        hold_off = true;
        for (Region& r : regions_) {
          if (r.tool == index) r.last_used = time_;
        }
      }
    }
  }
  // Coarsening renumbers nodes: not while a grasper holds (or is about to). Nor while a probe or
  // scope touches the tissue: undoing a split moves the surface (a displaced midpoint's triangles
  // become the flat coarse one), which can close over a tip resting in a dimple and trap it
  // inside (liver seeds 184 and 209 ended with the probe's proxy inside the organ).
  for (const Tool& t : tools_) {
    if (t.probe && !t.probe->contacts().empty()) hold_off = true;
  }
  if (hold_off) return;
  // Regions expire even where nothing was split (the knee refuses most splits): they would pile
  // up, and a known region is never refined again.
  const auto expired = std::erase_if(
      regions_, [&](const Region& r) { return time_ - r.last_used > a.coarsen_after; });
  if (expired > 0 && !tissue_->bisections().empty()) coarsen();
}

void SurgicalScene::refine(int tool, const Vec3& centre, Real radius) {
  const AdaptivitySpec& a = spec_.adaptivity;
  regions_.push_back({centre, radius, time_, tool});
  const BisectionReport report = tissue_->refine(centre, radius, a.edge_length, a.max_splits);
  splits_ += report.splits;
  splits_refused_ += report.refused;
  if (report.splits == 0) return;
  for (Tool& t : tools_)
    t.cutter.reset();  // its node and tet counts are stale; none has an open stroke
  update_damage(report.tets_before, report.changed, report.parents);
  follow_node_count();
}

void SurgicalScene::coarsen() {
  const Real margin = spec_.adaptivity.edge_length;
  const auto keep = [&](const Vec3& rest) {
    for (const Region& r : regions_) {
      if ((rest - r.centre).norm() <= r.radius + margin) return true;
    }
    return false;
  };
  bool any = false;
  const TetMesh& mesh = tissue_->mesh();
  for (const Bisection& s : tissue_->bisections()) {
    if (!keep(row3(mesh.rest, s.mid))) {
      any = true;
      break;
    }
  }
  if (!any) return;
  const int slots_before = std::max(damage_->num_slots(), mesh.num_tets());
  const CoarsenReport report = tissue_->coarsen(keep);
  splits_undone_ += report.undone;
  if (report.undone > 0) after_compaction(report.tet_map, slots_before);
}

void SurgicalScene::follow_node_count() {
  const int n = tissue_->mesh().num_nodes();
  prescribed_.mask = AxisMask::Zero(n, 3);
  prescribed_.position = Points::Zero(n, 3);
  prescribed_rows_.clear();
  surface_nodes_ = tissue_->surface().nodes;
}

void SurgicalScene::after_topology_change(int tets_before, std::span<const int> changed) {
  tissue_->topology_changed(tets_before, changed);
  // New pieces start undamaged: a parent search per cut frame would cost O(#changed x #tets);
  // the damage of a cut piece is the cut's own record.
  update_damage(tets_before, changed, {});
  follow_node_count();
  const TetMesh& mesh = tissue_->mesh();
  const int n = mesh.num_nodes();
  const int stable = stable_nodes();
  for (Tool& tool : tools_) {
    if (!tool.grasper) continue;
    for (const int v : std::vector<int>(tool.grasper->grabbed())) {
      if (v >= std::min(n, stable)) {
        if (const auto released = tool.grasper->on_vertex_removed(v)) {
          event(EventKind::release, static_cast<int>(&tool - tools_.data()),
                std::string(to_string(released->reason)) + " (cut away)");
        }
      }
    }
  }
}

tools::LocalForceModel SurgicalScene::force_model(int device) const {
  tools::LocalForceModel sum;
  bool first = true;
  for (const Tool& tool : tools_) {
    if (tool.spec.device != device || !tool.has_input) continue;
    tools::LocalForceModel m;
    m.reference_position = tool.tip;
    if (tool.probe) {
      m = tool.probe->hand_force_model();
    } else if (tool.grasper) {
      m.force = tool.hand_force;
    }
    // Bones push on the tool at its tip: the same model about the device position.
    m.force += tool.bone.force_at(m.reference_position);
    m.stiffness += tool.bone.stiffness;
    if (first) {
      sum = m;
      first = false;
    } else {
      sum.force += m.force_at(sum.reference_position);
      sum.stiffness += m.stiffness;
    }
  }
  return sum;
}

ToolView SurgicalScene::tool_view(int index) const {
  const Tool& tool = tools_.at(static_cast<std::size_t>(index));
  ToolView view;
  view.kind = tool.spec.kind;
  view.tip = tool.probe ? tool.probe->proxy() : tool.tip;
  view.direction = tool.direction;
  view.shaft_length = tool.spec.shaft_length;
  view.shaft_radius = tool.spec.shaft_radius;
  view.touching = tool.touching_bone || (tool.probe && !tool.probe->contacts().empty()) ||
                  tool.stroke ||
                  (tool.grasper && tool.grasper->phase() == tools::GraspPhase::holding);
  if (tool.grasper) view.jaws = tool.grasper->jaws();
  if (tool.probe) view.force_on_tissue = tool.probe->transmitted_force();
  return view;
}

std::optional<ScopeCamera> SurgicalScene::scope_camera() const {
  for (const Tool& tool : tools_) {
    if (tool.spec.kind != ToolKind::scope || !tool.has_input) continue;
    // Tilt d by the view angle towards -R e_y, about R e_x.
    const Real angle = tool.spec.view_angle_degrees * std::numbers::pi / 180;
    const Eigen::AngleAxis<Real> tilt(angle, tool.rotation.col(0));
    ScopeCamera camera;
    camera.eye = tool.tip;
    camera.forward = (tilt * tool.direction).normalized();
    camera.up = (tilt * tool.rotation.col(1)).normalized();
    camera.field_of_view_degrees = tool.spec.field_of_view_degrees;
    return camera;
  }
  return std::nullopt;
}

int SurgicalScene::stable_nodes() const {
  int stable = tissue_->mesh().num_nodes();
  for (const Tool& tool : tools_) {
    if (tool.cutter) stable = std::min(stable, tool.cutter->committed_nodes());
  }
  return stable;
}

bool SurgicalScene::state_finite() const {
  return tissue_->mesh().x.allFinite() && tissue_->mesh().v.allFinite();
}

}  // namespace incise::sim::surgery
