#include "sim/render/frame_encoder.h"

#include <chrono>
#include <stdexcept>
#include <string>

#include "sim/render/gl_api.h"
#include "sim/render/scene_renderer.h"

namespace incise::render {
namespace {

int checked_quality(int quality) {
  if (quality < 1 || quality > 100) {
    throw std::invalid_argument("JPEG quality " + std::to_string(quality) + " is not in 1..100");
  }
  return quality;
}

double milliseconds(std::chrono::steady_clock::duration duration) {
  return std::chrono::duration<double, std::milli>(duration).count();
}

}  // namespace

FrameEncoder::FrameEncoder(int width, int height, int quality)
    : quality_(checked_quality(quality)),
      framebuffer_(std::make_unique<Framebuffer>(width, height)) {}

void FrameEncoder::resize(int width, int height) {
  if (width == this->width() && height == this->height()) return;
  // Build the new one first, so that a failure leaves the encoder as it was.
  auto resized = std::make_unique<Framebuffer>(width, height);
  framebuffer_ = std::move(resized);
}

void FrameEncoder::render_jpeg(SceneRenderer& renderer, const Camera& camera,
                               const TissueView& tissue, const ToolView& tool,
                               std::vector<std::uint8_t>& jpeg) {
  render_jpeg(renderer, camera, tissue, std::span<const ToolView>(&tool, 1), jpeg);
}

void FrameEncoder::render_jpeg(SceneRenderer& renderer, const Camera& camera,
                               const TissueView& tissue, std::span<const ToolView> tools,
                               std::vector<std::uint8_t>& jpeg, std::span<const MarkView> marks) {
  using clock = std::chrono::steady_clock;
  const clock::time_point start = clock::now();
  renderer.render(*framebuffer_, camera, tissue, tools, marks);
  // The readback would wait for the drawing anyway; finishing first only splits the time.
  glFinish();
  const clock::time_point drawn = clock::now();
  framebuffer_->read_rgb(rgb_);
  const clock::time_point read = clock::now();
  encoder_.encode(rgb_, width(), height(), quality_, jpeg);
  const clock::time_point encoded = clock::now();
  timings_ = {milliseconds(drawn - start), milliseconds(read - drawn),
              milliseconds(encoded - read)};
}

}  // namespace incise::render
