#pragma once

#include <string>

#include "sim/render/render_error.h"

namespace incise::render {

// An EGL call failed. what() names the call and the error, e.g.
// "eglInitialize failed: EGL_NOT_INITIALIZED".
class EglError : public RenderError {
 public:
  // egl_error: the value eglGetError() returned; detail: optional context appended in brackets.
  EglError(const std::string& call, int egl_error, const std::string& detail = "");
  int egl_error() const { return egl_error_; }

 private:
  int egl_error_;
};

// "EGL_BAD_ALLOC" for EGL_BAD_ALLOC, "EGL_SUCCESS" for EGL_SUCCESS, "0x3100"-style hex otherwise.
std::string egl_error_name(int egl_error);

// An offscreen OpenGL core-profile context that needs no display server and no surface
// (EGL_KHR_surfaceless_context): drawing goes to framebuffer objects only (see Framebuffer).
//
// Display, in order of preference: Mesa's surfaceless platform, then the first EGL device that
// initialises (EGL_EXT_platform_device), then eglGetDisplay(EGL_DEFAULT_DISPLAY). On a headless
// Debian machine the first one gives Mesa llvmpipe.
//
// A context is current on at most one thread at a time. The constructor makes it current on the
// calling thread; another thread may take it over after release_current(). GL objects created
// while it is current (Framebuffer, MeshRenderer) must be destroyed before it, on a thread where
// it is current.
class EglContext {
 public:
  // Asks for OpenGL 4.5 core, falling back to 3.3 core. Throws EglError if no display
  // initialises or the context cannot be created or made current; RenderError if the display
  // lacks surfaceless contexts.
  EglContext();
  ~EglContext();
  EglContext(const EglContext&) = delete;
  EglContext& operator=(const EglContext&) = delete;

  // Makes this context current on the calling thread. Throws EglError.
  void make_current() const;
  // Releases the calling thread's current context, if it is this one.
  void release_current() const;

  // "surfaceless", "device" or "default": which display the constructor obtained.
  const std::string& platform() const { return platform_; }
  // GL_RENDERER and GL_VERSION, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)", "4.5 (Core Profile)...".
  const std::string& renderer() const { return renderer_; }
  const std::string& version() const { return version_; }
  int gl_major() const { return gl_major_; }
  int gl_minor() const { return gl_minor_; }

 private:
  void create_context();
  void read_gl_strings();
  void destroy() noexcept;

  // EGLDisplay and EGLContext (both pointers) kept opaque so that users of this header do not
  // pull in the EGL headers.
  void* display_ = nullptr;
  void* context_ = nullptr;
  std::string platform_;
  std::string renderer_;
  std::string version_;
  int gl_major_ = 0;
  int gl_minor_ = 0;
};

}  // namespace incise::render
