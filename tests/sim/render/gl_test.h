#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <memory>

#include "sim/render/egl_context.h"

namespace incise::render {

// Fixture for tests that draw: one headless context per suite, current on the test thread.
class GlTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    // The server renders with no display server; make sure no test leans on one by accident.
    unsetenv("DISPLAY");
    unsetenv("WAYLAND_DISPLAY");
    context = std::make_unique<EglContext>();
  }
  static void TearDownTestSuite() { context.reset(); }

  static inline std::unique_ptr<EglContext> context;
};

}  // namespace incise::render
