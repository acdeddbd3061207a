#pragma once
// A surgical scene (sim/surgery/) hosted by a session's SimEngine: the station's device i drives
// the scene's tools bound to device i (the task's tools[i]). One tick is a whole number of the
// scene's steps; the scene's dt is shortened to tick / ceil(tick / dt) (a shorter step is as
// stable). Within a tick each hand's tip and jaw move linearly and its orientation by slerp from
// the previous input to the new one. Deterministic, like the scene.
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "devices/device_state.h"
#include "sim/core/clone_ptr.h"
#include "sim/interact/tool_contact.h"
#include "sim/mesh/boundary_surface.h"
#include "sim/surgery/cut_walls.h"
#include "sim/surgery/scene_presets.h"
#include "sim/surgery/surgical_scene.h"

namespace incise::server::live {

class SurgeryWorld {
 public:
  // Throws std::invalid_argument for a bad tick (or as SurgicalScene does for a bad spec).
  SurgeryWorld(std::shared_ptr<const sim::surgery::SurgicalSceneSetup> setup, double tick_s);

  int substeps() const { return substeps_; }
  // One tick: hand h from from[h] to to[h] (the first two hands of the shorter span).
  void tick(std::span<const devices::DeviceState> from, std::span<const devices::DeviceState> to);
  // A copy is a deep one (SurgicalScene::clone): a checkpoint that replays bit for bit. (A
  // replay's seek restores one; nothing rebuilds the scene from its start any more.)
  SurgeryWorld(const SurgeryWorld&) = default;
  SurgeryWorld& operator=(const SurgeryWorld&) = default;

  // What device `hand` feels: the force on the hand and the PSD stiffness of its tools' local
  // force models (SurgicalScene::force_model), and 1 node in contact while one of them touches.
  const sim::ToolContact& contact(int hand) const {
    return contacts_[static_cast<std::size_t>(hand)];
  }

  const sim::surgery::SurgicalScene& scene() const { return *scene_; }
  // How much of its adaptivity the scene sheds from the next tick on (SurgicalScene::
  // set_shed_level).
  void set_shed_level(int level) { scene_->set_shed_level(level); }
  const sim::surgery::SurgicalSceneSetup& setup() const { return *setup_; }
  // The tissue's boundary; a new object whenever the topology changed (cuts, refinement).
  const std::shared_ptr<const sim::BoundarySurface>& surface() const { return surface_; }
  // Per face of surface(), 1 for a wall a cut opened; a new object with each new surface; null
  // for the palpation block (nothing cuts it).
  const std::shared_ptr<const std::vector<std::uint8_t>>& cut_faces() const { return cut_faces_; }
  // Per face of surface(), the tissue label of its tet (0..255), and per surface vertex its rest
  // position [m] (where the picture fixes the tissue's vessels); new objects with each new
  // surface.
  const std::shared_ptr<const std::vector<std::uint8_t>>& face_labels() const {
    return face_labels_;
  }
  const std::shared_ptr<const sim::Points>& surface_rest() const { return surface_rest_; }
  // The marked cut line's points as the tissue carries them now: each point moves with the
  // surface node nearest to it at rest (cuts and refinement renumber nodes, so it is looked up
  // each time; a few hundred distances).
  std::vector<sim::Vec3> marked_line() const;
  // The scene's events of the last tick (grab, release, cut, collision, never event).
  const std::vector<sim::surgery::SceneEvent>& events() const { return events_; }

 private:
  // The scene at its start (the constructor).
  void reset();
  void follow_surface();

  std::shared_ptr<const sim::surgery::SurgicalSceneSetup> setup_;
  double dt_ = 0;
  int substeps_ = 1;
  sim::ClonePtr<sim::surgery::SurgicalScene> scene_;
  std::vector<sim::surgery::ToolInput> inputs_;
  std::array<sim::ToolContact, 2> contacts_;  // per hand (SimEngine::kMaxHands)
  std::shared_ptr<const sim::BoundarySurface> surface_;
  std::optional<sim::surgery::CutWalls> cut_walls_;  // the tissue's boundary at the start
  std::shared_ptr<const std::vector<std::uint8_t>> cut_faces_;
  std::shared_ptr<const std::vector<std::uint8_t>> face_labels_;
  std::shared_ptr<const sim::Points> surface_rest_;
  std::vector<sim::surgery::SceneEvent> events_;
};

// The scene's input for a device state: tip, orientation (normalised), jaw, buttons.
sim::surgery::ToolInput tool_input(const devices::DeviceState& state);

}  // namespace incise::server::live
