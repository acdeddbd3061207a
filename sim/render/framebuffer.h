#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace incise::render {

// An offscreen render target: RGBA8 colour and 24-bit depth renderbuffers in one framebuffer
// object. Needs a current EglContext on the calling thread for its whole life, and must be
// destroyed before that context.
class Framebuffer {
 public:
  // Largest accepted width or height [pixels]: far above any streamed view, and within what every
  // GL 3.3 implementation supports for renderbuffers.
  static constexpr int max_size = 8192;

  // Throws std::invalid_argument unless 1 <= width, height <= max_size, and RenderError if the
  // implementation cannot build a complete framebuffer of that size.
  Framebuffer(int width, int height);
  ~Framebuffer();
  Framebuffer(const Framebuffer&) = delete;
  Framebuffer& operator=(const Framebuffer&) = delete;

  int width() const { return width_; }
  int height() const { return height_; }

  // Makes this the draw and read target, with a viewport covering all of it.
  void bind() const;
  // Binds, then sets every pixel to rgb (linear, each channel in [0, 1]) and depth to the far
  // plane.
  void clear(const Eigen::Vector3f& rgb) const;

  // Binds, then returns width * height * 3 bytes, RGB, rows from the top of the image down (the
  // order images and JPEG use; GL's own origin is the bottom-left corner).
  std::vector<std::uint8_t> read_rgb() const;
  // Same, into rgb (resized), so that a per-frame caller can reuse one buffer.
  void read_rgb(std::vector<std::uint8_t>& rgb) const;

 private:
  int width_;
  int height_;
  // GL object names.
  unsigned int framebuffer_ = 0;
  unsigned int colour_ = 0;
  unsigned int depth_ = 0;
};

}  // namespace incise::render
