#pragma once

// A tool script sampled in time (tool_script.h): each device's tip, direction and jaw at time t,
// as the tools' input.

#include <vector>

#include "sim/core/types.h"
#include "sim/surgery/surgical_scene.h"
#include "sim/surgery/tool_script.h"

namespace incise::sim::surgery {

// The track's input at time t [s] (held before the first and after the last keyframe).
// Allocates nothing. Precondition: track has a keyframe.
ToolInput sample_track(const DeviceTrack& track, Real t);

// Every device's input at time t into inputs (resized to the script's device count; no
// allocation once it has that size).
void sample_script(const ToolScript& script, Real t, std::vector<ToolInput>& inputs);

}  // namespace incise::sim::surgery
