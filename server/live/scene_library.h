#pragma once
// The scenes tasks refer to ("scenes/palpation.json"), compiled into the server from sim/scenes/
// so that a deployed server needs no source tree. A scene's version names the runtime and hashes
// the text: a recording stores it, and a replay refuses to run on another runtime or against a
// scene that has changed since.
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace incise::server::live {

// Surgical scene files live here; every other scene is a sim core scene (session_scene.h).
inline constexpr std::string_view kSurgicalScenePrefix = "scenes/surgery/";

struct SceneSource {
  std::string_view id;    // as tasks name it, e.g. "scenes/palpation.json"
  std::string_view text;  // the JSON
};

// The scene with this id, or nullopt.
std::optional<SceneSource> find_scene(std::string_view id);
// Every scene, in the order of their ids.
std::span<const SceneSource> all_scenes();
// An example probe data file for calibrating the scene (sim/scenes/calibration/X.json has
// X_pushes.csv beside it; docs/calibration.md), or nullopt.
std::optional<std::string_view> find_example_data(std::string_view scene_id);

// FNV-1a 64 of the text, 16 hex digits.
std::string text_hash(std::string_view text);

// The runtime that replays this server's recordings bit for bit; a recording of another one is
// refused (its scores stand). Runtime 1 ran the palpation block on the sim core's own simulation
// (sim::Simulation, sphere tips) and the surgical scenes on SurgicalScene; runtime 2 ran every
// scene on SurgicalScene (the block with probes); runtime 3 rounds the corotational and spring
// forces and the damage strain differently (the vectorised kernels, corotational_batch.h and
// mass_spring_model.cpp; the strain's closed-form eigenvalue) and records the physics' shedding
// level per tick (tick_record.h); runtime 4 makes a probe whose device first appears in the
// tissue only once it is clear of it (sim/surgery/surgical_scene_tool.h), leaves a second hand
// that has not reported out of the scene (SimEngine::tick) and rounds the damage strain in SIMD
// lanes (sim/tools/damage_strain.h); runtime 5 pulls tissue left inside out back toward its rest
// shape (SurgicalScene::inverted_tets_pulled); runtime 6 frees a probe's or scope's tip that the
// hand pulls back along its shaft (tools::Probe::set_shaft) and holds a scalpel's cut while tissue
// near its blade is inverted (cut::tangled_near). Anything that changes a simulation's bits for the
// same inputs takes the next number. Bit for bit holds on one kind of processor: the vectorised
// kernels are compiled twice (AVX2 with fused multiply-adds, and the baseline without) and the
// loader picks one, so a recording made on one kind may replay with other round-off on the other.
inline constexpr int kSceneRuntime = 6;

// What a recording stores: "<runtime>:<text_hash>", e.g. "6:85944171f73967e8". (Runtime 1 stored
// the bare hash.)
std::string scene_version(std::string_view text);

// "" if a recording of scene `id` whose version is `recorded` replays exactly on this server,
// whose scene text is `text`; else why not, in a sentence (the runtime that made it, or that
// the scene changed since).
std::string replay_refusal(std::string_view id, std::string_view recorded, std::string_view text);

}  // namespace incise::server::live
