#pragma once

#include <string>

#include "sim/core/types.h"
#include "sim/scene/scene.h"
#include "sim/scene/scene_error.h"

namespace incise::sim {

// Checks the value ranges stated in scene.h that need no mesh (selections are checked against
// the mesh when a scene is run or made a live block). Throws SceneError for the first problem, e.g.
//   material.E: must be positive (got -3)
void validate_scene(const Scene& scene);

// The fastest P-wave speed over the scene's materials [m/s]: the one that sets the stable step
// (and the l_min that keeps every material's step at or above a dt_min).
Real fastest_wave_speed(const Scene& scene);

// The shortest decimal form that reads back as the same double ("-3", "0.1", "1e-05"), for
// error messages.
std::string format_number(Real value);

}  // namespace incise::sim
