#include "sim/render/egl_context.h"

#include <EGL/egl.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <iostream>

#include "sim/render/framebuffer.h"

namespace incise::render {
namespace {

TEST(EglContext, CreatesCoreContextWithoutDisplayServer) {
  unsetenv("DISPLAY");
  unsetenv("WAYLAND_DISPLAY");
  const EglContext context;
  std::cout << "EGL platform: " << context.platform() << "\nGL_RENDERER: " << context.renderer()
            << "\nGL_VERSION: " << context.version() << "\n";
  EXPECT_FALSE(context.renderer().empty());
  EXPECT_FALSE(context.version().empty());
  EXPECT_GE(context.gl_major() * 10 + context.gl_minor(), 33);
  EXPECT_TRUE(context.platform() == "surfaceless" || context.platform() == "device" ||
              context.platform() == "default");
}

// The display is shared within the process: closing one context must not terminate it under
// another that is still in use.
TEST(EglContext, SecondContextCanComeAndGoWhileFirstRenders) {
  unsetenv("DISPLAY");
  const EglContext first;
  {
    const EglContext second;
    EXPECT_EQ(second.platform(), first.platform());
  }
  first.make_current();
  const Framebuffer target(4, 4);
  target.clear(Eigen::Vector3f(1.0f, 0.0f, 0.0f));
  const std::vector<std::uint8_t> rgb = target.read_rgb();
  EXPECT_EQ(rgb[0], 255);
  EXPECT_EQ(rgb[1], 0);
}

TEST(EglContext, ReleaseAndMakeCurrentAgain) {
  unsetenv("DISPLAY");
  const EglContext context;
  context.release_current();
  context.make_current();
  const Framebuffer target(2, 2);
  target.clear(Eigen::Vector3f(0.0f, 1.0f, 0.0f));
  EXPECT_EQ(target.read_rgb()[1], 255);
}

TEST(EglError, NamesTheCallAndTheError) {
  const EglError error("eglInitialize", EGL_NOT_INITIALIZED);
  EXPECT_STREQ(error.what(), "eglInitialize failed: EGL_NOT_INITIALIZED");
  EXPECT_EQ(error.egl_error(), EGL_NOT_INITIALIZED);
  EXPECT_STREQ(EglError("eglCreateContext", EGL_BAD_MATCH, "core 4.5").what(),
               "eglCreateContext failed: EGL_BAD_MATCH (core 4.5)");
  EXPECT_EQ(egl_error_name(EGL_BAD_ALLOC), "EGL_BAD_ALLOC");
  EXPECT_EQ(egl_error_name(0x1234), "0x1234");
}

}  // namespace
}  // namespace incise::render
