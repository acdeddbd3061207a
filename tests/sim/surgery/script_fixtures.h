#pragma once
// What the tool-script and track-sampling tests share: a scene with places and tools but no mesh.
#include <gtest/gtest.h>

#include "sim/core/types.h"
#include "sim/surgery/scene_presets.h"
#include "sim/surgery/surgical_scene.h"

namespace incise::sim::surgery::testing {

// A scene for scripts without meshing: the places and tools a script may refer to.
inline SurgicalSceneSetup scripted_scene() {
  SurgicalSceneSetup scene;
  scene.name = "test";
  scene.spec.tools = {make_tool(ToolKind::probe, 0), make_tool(ToolKind::grasper, 1)};
  scene.landmarks = {{"horn", Vec3(0.01, 0, 0)}, {"notch", Vec3(0, 0.02, 0)}};
  scene.portals = {{"medial", Vec3(0, 0, 0.05), Vec3(0, 0, -1)}};
  scene.cut_target = {Vec3(-0.01, 0, 0), Vec3(0, 0, 0.001), Vec3(0.01, 0, 0)};
  return scene;
}

inline void expect_near(const Vec3& a, const Vec3& b, Real tolerance = 1e-15) {
  EXPECT_LT((a - b).norm(), tolerance) << a.transpose() << " vs " << b.transpose();
}

}  // namespace incise::sim::surgery::testing
