#include "sim/render/frame_encoder.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <stdexcept>

#include "gl_test.h"
#include "scene_test_util.h"
#include "sim/render/jpeg.h"
#include "sim/render/scene_renderer.h"

namespace incise::render {
namespace {

using FrameEncoderTest = GlTest;

Camera oblique_camera() {
  Camera camera;
  camera.eye = Eigen::Vector3d(0.02, -0.12, 0.12);
  camera.target = Eigen::Vector3d(0.0, 0.0, 0.03);
  camera.up = Eigen::Vector3d::UnitZ();
  camera.fov_y_deg = 40.0;
  return camera;
}

test::Surface tissue() {
  return test::square_surface(0.03, 12, Eigen::Matrix3d::Identity(), Eigen::Vector3d(0, 0, 0.03));
}

ToolView tool() {
  ToolView tool;
  tool.tip = Eigen::Vector3d(0.005, 0.0, 0.04);
  tool.shaft_direction = Eigen::Vector3d(0.3, 0.2, 1.0);
  return tool;
}

double mean_abs_difference(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b) {
  double sum = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i)
    sum += std::abs(a[i] - b[i]);
  return sum / static_cast<double>(a.size());
}

// The JPEG decodes to the requested size and to the raw frame within compression error; the raw
// frame is exactly what the renderer draws into a framebuffer of that size.
TEST_F(FrameEncoderTest, JpegDecodesToTheRenderedFrame) {
  SceneRenderer renderer;
  FrameEncoder encoder(200, 150, 80);
  const test::Surface surface = tissue();
  std::vector<std::uint8_t> jpeg;
  encoder.render_jpeg(renderer, oblique_camera(), surface.view(), tool(), jpeg);

  const Framebuffer reference(200, 150);
  renderer.render(reference, oblique_camera(), surface.view(), tool());
  EXPECT_EQ(encoder.rgb(), reference.read_rgb());

  const RgbImage decoded = decode_jpeg(jpeg);
  EXPECT_EQ(decoded.width, 200);
  EXPECT_EQ(decoded.height, 150);
  ASSERT_EQ(decoded.rgb.size(), encoder.rgb().size());
  // Flat shading and a smooth backdrop: quality 80 keeps the mean error within a few levels
  // (edges of the tool and tissue carry most of it).
  EXPECT_LT(mean_abs_difference(decoded.rgb, encoder.rgb()), 2.5);
  // A JPEG of a mostly flat picture is far smaller than the raw frame.
  EXPECT_LT(jpeg.size(), encoder.rgb().size() / 10);

  const FrameTimings& timings = encoder.timings();
  EXPECT_GT(timings.render_ms, 0.0);
  EXPECT_GT(timings.encode_ms, 0.0);
  EXPECT_DOUBLE_EQ(timings.total_ms(), timings.render_ms + timings.readback_ms + timings.encode_ms);
}

TEST_F(FrameEncoderTest, HigherQualityIsCloserAndLarger) {
  SceneRenderer renderer;
  const test::Surface surface = tissue();
  std::vector<std::uint8_t> low;
  std::vector<std::uint8_t> high;
  FrameEncoder coarse(160, 120, 30);
  coarse.render_jpeg(renderer, oblique_camera(), surface.view(), tool(), low);
  FrameEncoder fine(160, 120, 95);
  fine.render_jpeg(renderer, oblique_camera(), surface.view(), tool(), high);
  EXPECT_LT(low.size(), high.size());
  EXPECT_LT(mean_abs_difference(decode_jpeg(high).rgb, fine.rgb()),
            mean_abs_difference(decode_jpeg(low).rgb, coarse.rgb()));
}

// Frames of one size reuse the caller's vector: no reallocation once it has room.
TEST_F(FrameEncoderTest, ReusesTheCallersJpegBuffer) {
  SceneRenderer renderer;
  FrameEncoder encoder(96, 64);
  const test::Surface surface = tissue();
  std::vector<std::uint8_t> jpeg;
  encoder.render_jpeg(renderer, oblique_camera(), surface.view(), tool(), jpeg);
  const std::vector<std::uint8_t> first = jpeg;
  jpeg.reserve(2 * jpeg.size());
  const std::uint8_t* storage = jpeg.data();
  encoder.render_jpeg(renderer, oblique_camera(), surface.view(), tool(), jpeg);
  EXPECT_EQ(jpeg.data(), storage);
  EXPECT_EQ(jpeg, first);  // same scene, same bytes
}

TEST_F(FrameEncoderTest, ResizeChangesTheFrameSize) {
  SceneRenderer renderer;
  FrameEncoder encoder(64, 48);
  EXPECT_EQ(encoder.width(), 64);
  EXPECT_EQ(encoder.height(), 48);
  const test::Surface surface = tissue();
  std::vector<std::uint8_t> jpeg;

  encoder.resize(120, 90);
  EXPECT_EQ(encoder.width(), 120);
  EXPECT_EQ(encoder.height(), 90);
  encoder.render_jpeg(renderer, oblique_camera(), surface.view(), tool(), jpeg);
  const RgbImage decoded = decode_jpeg(jpeg);
  EXPECT_EQ(decoded.width, 120);
  EXPECT_EQ(decoded.height, 90);
  EXPECT_EQ(encoder.rgb().size(), 120u * 90u * 3u);

  // The resized frame is the scene at the new size, not a stretched old one.
  FrameEncoder direct(120, 90);
  std::vector<std::uint8_t> direct_jpeg;
  direct.render_jpeg(renderer, oblique_camera(), surface.view(), tool(), direct_jpeg);
  EXPECT_EQ(encoder.rgb(), direct.rgb());

  encoder.resize(120, 90);  // unchanged: no-op
  EXPECT_EQ(encoder.width(), 120);
  EXPECT_THROW(encoder.resize(0, 90), std::invalid_argument);
  EXPECT_THROW(encoder.resize(120, Framebuffer::max_size + 1), std::invalid_argument);
  EXPECT_EQ(encoder.width(), 120);  // a rejected resize keeps the old size
  EXPECT_EQ(encoder.height(), 90);
}

TEST_F(FrameEncoderTest, RejectsInvalidSettings) {
  EXPECT_THROW(FrameEncoder(0, 10), std::invalid_argument);
  EXPECT_THROW(FrameEncoder(10, 10, 0), std::invalid_argument);
  try {
    FrameEncoder(10, 10, 101);
    ADD_FAILURE() << "quality 101 was accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_STREQ(error.what(), "JPEG quality 101 is not in 1..100");
  }
  EXPECT_EQ(FrameEncoder(10, 10).quality(), 80);
}

}  // namespace
}  // namespace incise::render
