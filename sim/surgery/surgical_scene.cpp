// A surgical scene's construction and its step, which calls on the parts in their own files:
// surgical_scene_validation, _far_field, _grasping, _cutting, _cutting_resistance, _bone_contact,
// _topology and _adaptivity (.cpp).
#include "sim/surgery/surgical_scene.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>

#include "sim/collide/inside_surface.h"
#include "sim/surgery/surgical_scene_far_field.h"
#include "sim/surgery/surgical_scene_tool.h"
#include "sim/surgery/surgical_scene_validation.h"

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
    case EventKind::grasp:
      return "grasp";
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

SurgicalScene::SurgicalScene(SurgicalSceneSpec spec) : spec_(std::move(spec)) {
  validate(spec_);
  std::vector<char> far;
  ModelFactory model = spec_.model;
  if (spec_.far_field.enabled) {
    FarFieldSetup setup = set_up_far_field(spec_);
    far = std::move(setup.far);
    far_guard_ = setup.guard;
    model = std::move(setup.model);
  }
  tissue_ = std::make_unique<TissueBody>(spec_.tissue, model, spec_.fixed, spec_.dt,
                                         spec_.wave_speed, spec_.damping_time, far);
  tissue_->set_ambient_damping(spec_.ambient_damping);
  auto bones = std::make_shared<std::vector<collide::RigidBody>>();
  for (std::size_t b = 0; b < spec_.bones.size(); ++b) {
    try {
      bones->emplace_back(spec_.bones[b].vertices, spec_.bones[b].triangles);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("surgical scene: bones[" + std::to_string(b) + "] (" +
                                  spec_.bones[b].name + "): " + e.what());
    }
  }
  bones_ = std::move(bones);
  bone_depths_.assign(bones_->size(), 0);
  bone_touching_.assign(bones_->size(), 0);
  for (const ToolSpec& t : spec_.tools) {
    Tool tool;
    tool.spec = t;
    tool.spec.probe.contact.time_step = spec_.dt;
    if (t.kind == ToolKind::scope) tool.spec.probe.radius = t.shaft_radius;
    if (t.kind == ToolKind::grasper) tool.grasper.emplace(t.grasp);
    tools_.push_back(std::move(tool));
  }
  tools::DamageSettings damage = spec_.damage;
  damage.protected_structures = static_cast<int>(bones_->size());
  damage_ = std::make_unique<tools::DamageTracker>(tissue_->mesh(), damage);
  damage_alive_.assign(static_cast<std::size_t>(tissue_->mesh().num_tets()), 1);
  const TetMesh& mesh = tissue_->mesh();
  prescribed_.mask = AxisMask::Zero(mesh.num_nodes(), 3);
  prescribed_.position = Points::Zero(mesh.num_nodes(), 3);
  surface_nodes_ = tissue_->surface().nodes;
}

SurgicalScene::~SurgicalScene() = default;

SurgicalScene::SurgicalScene(const SurgicalScene&) = default;

std::unique_ptr<SurgicalScene> SurgicalScene::clone() const {
  auto copy = std::unique_ptr<SurgicalScene>(new SurgicalScene(*this));
  for (Tool& tool : copy->tools_) {
    if (tool.cutter) tool.cutter->rebind(copy->tissue_->mesh());
  }
  return copy;
}

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
    tool.previous_tip = tool.tip;
    const auto d = static_cast<std::size_t>(tool.spec.device);
    if (d >= inputs.size()) continue;
    tool.input = inputs[d];
    tool.rotation = tool.input.orientation.normalized().toRotationMatrix();
    tool.direction = tool.rotation.col(2);
    tool.tip = tool.input.tip;
    if (!tool.has_input) tool.previous_tip = tool.tip;  // placed now: no motion yet
    tool.has_input = true;
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
        if (!tool.probe) {
          // The tip enters clear of the tissue (surgical_scene_tool.h): not inside it, and not in
          // it deeper than a step may take it (touching is clear).
          const collide::Sphere tip{tool.tip,
                                    tool.spec.probe.radius - tool.spec.probe.allowed_penetration};
          tissue_->bvh().overlapping_triangles(mesh.x, tip, tool.ray_triangles);
          if (!tool.ray_triangles.empty() ||
              collide::inside_closed_surface(tissue_->bvh(), mesh.x, tool.tip,
                                             tool.ray_triangles)) {
            break;
          }
          tool.probe.emplace(tool.spec.probe, tool.tip);
        }
        tool.probe->set_shaft(tool.spec.upright ? Vec3(Vec3::UnitZ()) : Vec3(-tool.direction));
        tool.probe->step(tool.tip, tissue_->bvh(), mesh.x, mesh.v, tissue_->masses(),
                         tissue_->forces(), &tissue_->inverse_masses());
        break;
      case ToolKind::grasper:
        grasp(tool, static_cast<int>(k));
        break;
      case ToolKind::scalpel:
        resist_cut(tool);
        break;
    }
    bones(tool, static_cast<int>(k));
  }
  tissue_->end_step(spec_.dt, spec_.gravity, prescribed_);
  recover_inverted();
  // Bone contacts: a rising edge per bone is a collision with a protected structure.
  for (std::size_t b = 0; b < bones_->size(); ++b) {
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

void SurgicalScene::recover_inverted() {
  const bool inverted = tissue_->model().health().inverted_elements > 0;
  // A tangle that a pull undoes for a step and the dynamics redo is still the same tangle: the
  // clocks restart only once the tissue has stayed clean for kRecoverAfterS.
  clean_time_ = inverted ? 0 : clean_time_ + spec_.dt;
  if (clean_time_ >= kRecoverAfterS) {
    inverted_time_ = 0;
    pulling_time_ = 0;
  }
  if (!inverted) return;
  inverted_time_ += spec_.dt;
  if (inverted_time_ < kRecoverAfterS) return;
  // Each tool's reach, where an inverted tet is the tool's business: a tool that works the
  // tissue (a probe or scope in contact, a grasper closing or holding, a scalpel's open stroke)
  // reaches kRecoverWorkReach around its tip (a palpation press squeezes tets inside out a
  // centimetre from the ball, and pulling them fought the press); any other tool its tip ball,
  // jaws or blade, and kRecoverClearance beyond. A scalpel whose cut waits on a tangle at its
  // blade (cut::tangled_near) is not working: the cut waits for this recovery.
  tool_segments_.clear();
  for (const Tool& tool : tools_) {
    if (!tool.has_input) continue;
    const bool working = tool.touching_bone || (tool.stroke && !tool.cut_waiting) ||
                         (tool.probe && !tool.probe->contacts().empty()) ||
                         (tool.grasper && (tool.grasper->phase() == tools::GraspPhase::closing ||
                                           tool.grasper->phase() == tools::GraspPhase::holding));
    const Vec3 touch = tool.probe ? tool.probe->proxy() : tool.tip;
    Vec3 back = tool.tip;  // the far end of what the tool puts in the tissue
    Real radius = kRecoverClearance;
    switch (tool.spec.kind) {
      case ToolKind::probe:
      case ToolKind::scope:
        radius += tool.spec.probe.radius;
        break;
      case ToolKind::grasper:
        back = tool.tip - tool.spec.grasp.jaw_length * tool.direction;
        radius += tool.spec.grasp.jaw_length * std::sin(tool.spec.max_jaw_angle / 2);
        break;
      case ToolKind::scalpel:
        back = tool.tip - tool.spec.blade_length * tool.direction;
        break;
    }
    tool_segments_.push_back({touch, back, working ? std::max(radius, kRecoverWorkReach) : radius});
  }
  // A tangle that outlasts the pull (a sliver held flat against a bone) is pulled twice as hard
  // for every kRecoverDoublingS it has been pulled, up to a full projection; counted in whole
  // doublings, so that a replay rounds exactly as the run did.
  const int doublings = static_cast<int>(std::min(Real(30), pulling_time_ / kRecoverDoublingS));
  const Real fraction = std::min(Real(1), std::ldexp(spec_.dt / kRecoverTimeS, doublings));
  const int pulled = tissue_->recover_inverted(fraction, tool_segments_, &prescribed_.mask);
  if (pulled > 0) pulling_time_ += spec_.dt;
  inverted_tets_pulled_ += pulled;
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
    } else {
      m.force = tool.cutting_force;  // a scalpel's (zero for any other tool)
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
  view.blade_depth = tool.blade.depth;
  view.side = tool.rotation.col(0);
  view.has_input = tool.has_input;
  view.tip_radius = tool.spec.probe.radius;
  if (tool.spec.kind == ToolKind::grasper) {
    view.jaw_angle = std::clamp(tool.input.jaw, 0.0, 1.0) * tool.spec.max_jaw_angle;
    view.jaw_length = tool.spec.grasp.jaw_length;
  }
  if (tool.spec.kind == ToolKind::scalpel) view.blade_length = tool.spec.blade_length;
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

bool SurgicalScene::state_finite() const {
  return tissue_->mesh().x.allFinite() && tissue_->mesh().v.allFinite();
}

}  // namespace incise::sim::surgery
