#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "sim/render/camera.h"
#include "sim/render/framebuffer.h"
#include "sim/render/jpeg.h"

namespace incise::render {

// Declared in sim/render/scene_renderer.h, which also includes this header.
class SceneRenderer;
struct TissueView;
struct ToolView;
struct MarkView;

// Time spent in each stage of the last FrameEncoder::render_jpeg [ms].
struct FrameTimings {
  double render_ms = 0;    // upload + drawing, waited for with glFinish
  double readback_ms = 0;  // glReadPixels and row flip
  double encode_ms = 0;    // JPEG compression
  double total_ms() const { return render_ms + readback_ms + encode_ms; }
};

// Renders scenes into an owned Framebuffer and encodes them as JPEG, reusing its framebuffer,
// pixel buffer and compressor from frame to frame. Needs a current EglContext for its whole
// life (the same one as the SceneRenderer it is given); one per render thread.
class FrameEncoder {
 public:
  // Throws std::invalid_argument for a size outside 1..Framebuffer::max_size or a quality
  // outside 1..100; RenderError or JpegError if the framebuffer or compressor cannot be made.
  FrameEncoder(int width, int height, int quality = 80);

  // New framebuffer of this size; no-op if unchanged. Throws like the constructor.
  void resize(int width, int height);
  int width() const { return framebuffer_->width(); }
  int height() const { return framebuffer_->height(); }
  int quality() const { return quality_; }

  // Renders the scene, reads it back and encodes it; jpeg is overwritten (its capacity is
  // reused, so a caller that keeps the vector does not allocate per frame). Throws like
  // SceneRenderer::render and JpegEncoder::encode.
  void render_jpeg(SceneRenderer& renderer, const Camera& camera, const TissueView& tissue,
                   const ToolView& tool, std::vector<std::uint8_t>& jpeg);
  // The same with any number of tools (a two-handed station's) and marks on the tissue.
  void render_jpeg(SceneRenderer& renderer, const Camera& camera, const TissueView& tissue,
                   std::span<const ToolView> tools, std::vector<std::uint8_t>& jpeg,
                   std::span<const MarkView> marks = {});

  // The raw frame behind the last JPEG: width * height * 3 bytes, RGB, top row first.
  const std::vector<std::uint8_t>& rgb() const { return rgb_; }
  const FrameTimings& timings() const { return timings_; }

 private:
  int quality_;
  std::unique_ptr<Framebuffer> framebuffer_;
  std::vector<std::uint8_t> rgb_;
  JpegEncoder encoder_;
  FrameTimings timings_;
};

}  // namespace incise::render
