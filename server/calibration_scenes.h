#pragma once
// The scenes tissue calibration can fit (docs/calibration.md): the server's sim core scenes
// (scene_library.h) on a box mesh without adaptivity, and what a job needs of one.
#include <string>
#include <string_view>
#include <vector>

#include "sim/calibrate/probe_data.h"
#include "sim/mesh/tet_mesh.h"
#include "sim/scene/scene.h"

namespace incise::server {

struct CalibrationScene {
  std::string id;         // "scenes/calibration/cube.json"
  std::string title;      // "cube (mss, 125 nodes)"
  std::string model;      // the scene file's model name
  bool per_node = false;  // the mass-spring model: seed 004's per-node moduli too
  bool has_example = false;
};

// The same list every call (the scenes are compiled in); thread-safe.
const std::vector<CalibrationScene>& calibration_scenes();

struct CalibrationSetup {
  sim::Scene scene;
  sim::TetMesh mesh;
  sim::calibrate::ProbeData data;
};

// The scene with this id, its mesh and the data parsed and attached to it. Throws
// sim::calibrate::CalibrationError for data or a scene calibration cannot use, with what and
// where: "data: line 7: ...", "scene ...: ...".
CalibrationSetup calibration_setup(std::string_view scene_id, std::string_view csv);

// What one node's job may ask for, so that no upload can take the server's memory or its
// calibration thread for hours: at most kMaxJobContacts contacts and kMaxJobSamples samples; lm's
// Jacobian (residuals by parameters) at most kMaxJacobianEntries doubles; cmaes's covariance at
// most kMaxCmaesParameters square. Throws sim::calibrate::CalibrationError saying which.
inline constexpr std::size_t kMaxJobContacts = 64;
inline constexpr std::size_t kMaxJobSamples = 200'000;
inline constexpr double kMaxJacobianEntries = 2.5e7;
inline constexpr int kMaxCmaesParameters = 500;
void check_job_size(const CalibrationSetup& setup, bool per_node, std::string_view method);

}  // namespace incise::server
