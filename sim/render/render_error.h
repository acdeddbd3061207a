#pragma once

#include <stdexcept>
#include <string>

namespace incise::render {

// Base of every error the renderer reports: a failed EGL/GL/JPEG operation. Bad arguments
// (sizes, quality, mesh shapes) are std::invalid_argument instead, since they are caller bugs.
class RenderError : public std::runtime_error {
 public:
  explicit RenderError(const std::string& what) : std::runtime_error(what) {}
};

}  // namespace incise::render
