#include "sim/render/framebuffer.h"

#include <algorithm>
#include <cstddef>
#include <stdexcept>
#include <string>

#include "sim/render/gl_api.h"
#include "sim/render/render_error.h"

namespace incise::render {

Framebuffer::Framebuffer(int width, int height) : width_(width), height_(height) {
  if (width < 1 || width > max_size || height < 1 || height > max_size) {
    throw std::invalid_argument(
        "framebuffer size " + std::to_string(width) + "x" + std::to_string(height) +
        " is invalid: width and height must be 1.." + std::to_string(max_size));
  }
  // Drop errors left by earlier calls so that the check below reports only this construction's.
  while (glGetError() != GL_NO_ERROR) {
  }
  glGenFramebuffers(1, &framebuffer_);
  glGenRenderbuffers(1, &colour_);
  glGenRenderbuffers(1, &depth_);

  glBindRenderbuffer(GL_RENDERBUFFER, colour_);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
  glBindRenderbuffer(GL_RENDERBUFFER, depth_);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
  glBindRenderbuffer(GL_RENDERBUFFER, 0);

  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour_);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_);
  const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
  const GLenum error = glGetError();
  if (status != GL_FRAMEBUFFER_COMPLETE || error != GL_NO_ERROR) {
    glDeleteFramebuffers(1, &framebuffer_);
    glDeleteRenderbuffers(1, &colour_);
    glDeleteRenderbuffers(1, &depth_);
    throw RenderError("framebuffer " + std::to_string(width) + "x" + std::to_string(height) +
                      " is incomplete (status " + std::to_string(status) + ", GL error " +
                      std::to_string(error) + ")");
  }
}

Framebuffer::~Framebuffer() {
  glDeleteFramebuffers(1, &framebuffer_);
  glDeleteRenderbuffers(1, &colour_);
  glDeleteRenderbuffers(1, &depth_);
}

void Framebuffer::bind() const {
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  glViewport(0, 0, width_, height_);
}

void Framebuffer::clear(const Eigen::Vector3f& rgb) const {
  bind();
  glClearColor(rgb.x(), rgb.y(), rgb.z(), 1.0f);
  glClearDepth(1.0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
}

std::vector<std::uint8_t> Framebuffer::read_rgb() const {
  std::vector<std::uint8_t> rgb;
  read_rgb(rgb);
  return rgb;
}

void Framebuffer::read_rgb(std::vector<std::uint8_t>& rgb) const {
  bind();
  const std::size_t row_bytes = static_cast<std::size_t>(width_) * 3;
  rgb.resize(row_bytes * height_);
  // RGB rows of odd widths are not 4-byte aligned.
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  glReadPixels(0, 0, width_, height_, GL_RGB, GL_UNSIGNED_BYTE, rgb.data());
  for (int top = 0, bottom = height_ - 1; top < bottom; ++top, --bottom) {
    std::swap_ranges(rgb.begin() + top * row_bytes, rgb.begin() + (top + 1) * row_bytes,
                     rgb.begin() + bottom * row_bytes);
  }
}

}  // namespace incise::render
