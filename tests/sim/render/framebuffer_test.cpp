#include "sim/render/framebuffer.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "gl_test.h"

namespace incise::render {
namespace {

using FramebufferTest = GlTest;

TEST_F(FramebufferTest, ClearReadsBackExactBytes) {
  const Framebuffer target(7, 5);
  target.clear(Eigen::Vector3f(51.0f, 102.0f, 204.0f) / 255.0f);
  const std::vector<std::uint8_t> rgb = target.read_rgb();
  ASSERT_EQ(rgb.size(), 7u * 5u * 3u);
  for (std::size_t i = 0; i < rgb.size(); i += 3) {
    EXPECT_EQ(rgb[i], 51);
    EXPECT_EQ(rgb[i + 1], 102);
    EXPECT_EQ(rgb[i + 2], 204);
  }
}

// GL counts rows from the bottom; read_rgb must return the top row first. An odd width also
// checks that rows are packed without padding.
TEST_F(FramebufferTest, ReadbackPutsTopRowFirst) {
  const int width = 33;
  const int height = 20;
  const Framebuffer target(width, height);
  target.clear(Eigen::Vector3f::Zero());
  glEnable(GL_SCISSOR_TEST);
  glScissor(0, height / 2, width, height - height / 2);  // GL's upper half
  glClearColor(1.0f, 1.0f, 1.0f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  glDisable(GL_SCISSOR_TEST);

  const std::vector<std::uint8_t> rgb = target.read_rgb();
  for (int row = 0; row < height; ++row) {
    const std::uint8_t expected = row < height / 2 ? 255 : 0;
    for (int column = 0; column < width; ++column) {
      for (int channel = 0; channel < 3; ++channel) {
        ASSERT_EQ(rgb[(row * width + column) * 3 + channel], expected)
            << "row " << row << " column " << column;
      }
    }
  }
}

TEST_F(FramebufferTest, ReusedBufferIsResized) {
  const Framebuffer target(3, 2);
  target.clear(Eigen::Vector3f::Ones());
  std::vector<std::uint8_t> rgb(1000, 7);
  target.read_rgb(rgb);
  EXPECT_EQ(rgb.size(), 18u);
  EXPECT_EQ(rgb.back(), 255);
}

TEST_F(FramebufferTest, RejectsInvalidSizesClearly) {
  for (const auto& [width, height] : {std::pair{0, 10}, std::pair{10, 0}, std::pair{-1, 5},
                                      std::pair{8193, 1}, std::pair{1, 8193}}) {
    try {
      const Framebuffer target(width, height);
      ADD_FAILURE() << width << "x" << height << " was accepted";
    } catch (const std::invalid_argument& error) {
      EXPECT_EQ(std::string(error.what()), "framebuffer size " + std::to_string(width) + "x" +
                                               std::to_string(height) +
                                               " is invalid: width and height must be 1..8192");
    }
  }
}

TEST_F(FramebufferTest, AcceptsTheLargestSide) {
  const Framebuffer target(Framebuffer::max_size, 1);
  EXPECT_EQ(target.width(), 8192);
}

}  // namespace
}  // namespace incise::render
