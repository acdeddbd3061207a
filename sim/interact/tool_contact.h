#pragma once

#include "sim/core/types.h"

namespace incise::sim {

// What a hand's tools do to the hand at the end of a tick (server/live/surgery_world.h): the
// force and its linearisation, the local force model the station agent renders.
struct ToolContact {
  Vec3 force_on_tool = Vec3::Zero();  // on the hand [N]
  // K with force_on_tool(c) ~= force_on_tool(c0) - K (c - c0), symmetric PSD (a haptic device
  // renders F0 - K (c - c0) passively only for K PSD; sim/tools/force_model.h).
  Mat3 stiffness = Mat3::Zero();
  int nodes_in_contact = 0;  // 1 while a tool of the hand touches, else 0
};

}  // namespace incise::sim
