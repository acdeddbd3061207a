#include "sim/render/egl_context.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstdio>
#include <map>
#include <mutex>
#include <string_view>
#include <utility>
#include <vector>

#include "sim/render/gl_api.h"

namespace incise::render {
namespace {

// EGL extension strings are space-separated names; a plain substring search would match
// prefixes (EGL_KHR_create_context in EGL_KHR_create_context_no_error).
bool has_extension(const char* extensions, std::string_view name) {
  if (extensions == nullptr) return false;
  const std::string_view list(extensions);
  std::size_t begin = 0;
  while (begin < list.size()) {
    std::size_t end = list.find(' ', begin);
    if (end == std::string_view::npos) end = list.size();
    if (list.substr(begin, end - begin) == name) return true;
    begin = end + 1;
  }
  return false;
}

// EGL displays are process-wide: the same arguments give the same EGLDisplay, and eglTerminate
// invalidates it for every context created on it. Count the live EglContexts per display so that
// only the last one terminates it.
std::mutex& display_users_mutex() {
  static std::mutex mutex;
  return mutex;
}

std::map<EGLDisplay, int>& display_users() {
  static std::map<EGLDisplay, int> users;
  return users;
}

// Initialises the display and counts one user; on failure stores the EGL error and returns false.
bool acquire_display(EGLDisplay display, EGLint& error) {
  if (display == EGL_NO_DISPLAY) {
    error = eglGetError();
    return false;
  }
  std::lock_guard lock(display_users_mutex());
  EGLint major = 0;
  EGLint minor = 0;
  if (eglInitialize(display, &major, &minor) != EGL_TRUE) {
    error = eglGetError();
    return false;
  }
  ++display_users()[display];
  return true;
}

void release_display(EGLDisplay display) {
  std::lock_guard lock(display_users_mutex());
  auto user = display_users().find(display);
  if (user == display_users().end()) return;
  if (--user->second == 0) {
    display_users().erase(user);
    eglTerminate(display);
  }
}

struct OpenedDisplay {
  EGLDisplay display;
  const char* platform;
};

OpenedDisplay open_display() {
  const char* client_extensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  const auto get_platform_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
      eglGetProcAddress("eglGetPlatformDisplayEXT"));
  const bool platform_base =
      get_platform_display != nullptr && has_extension(client_extensions, "EGL_EXT_platform_base");
  EGLint error = EGL_SUCCESS;

  if (platform_base && has_extension(client_extensions, "EGL_MESA_platform_surfaceless")) {
    EGLDisplay display =
        get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (acquire_display(display, error)) return {display, "surfaceless"};
  }

  if (platform_base && has_extension(client_extensions, "EGL_EXT_platform_device") &&
      has_extension(client_extensions, "EGL_EXT_device_enumeration")) {
    const auto query_devices =
        reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    EGLint count = 0;
    if (query_devices != nullptr && query_devices(0, nullptr, &count) == EGL_TRUE && count > 0) {
      std::vector<EGLDeviceEXT> devices(count);
      query_devices(count, devices.data(), &count);
      for (EGLint i = 0; i < count; ++i) {
        EGLDisplay display = get_platform_display(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
        if (acquire_display(display, error)) return {display, "device"};
      }
    }
  }

  EGLDisplay display = eglGetDisplay(EGL_DEFAULT_DISPLAY);
  if (acquire_display(display, error)) return {display, "default"};
  throw EglError("eglInitialize", error, "no surfaceless, device or default EGL display");
}

}  // namespace

EglError::EglError(const std::string& call, int egl_error, const std::string& detail)
    : RenderError(call + " failed: " + egl_error_name(egl_error) +
                  (detail.empty() ? "" : " (" + detail + ")")),
      egl_error_(egl_error) {}

std::string egl_error_name(int egl_error) {
  switch (egl_error) {
    case EGL_SUCCESS:
      return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED:
      return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS:
      return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC:
      return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE:
      return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG:
      return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT:
      return "EGL_BAD_CONTEXT";
    case EGL_BAD_CURRENT_SURFACE:
      return "EGL_BAD_CURRENT_SURFACE";
    case EGL_BAD_DISPLAY:
      return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH:
      return "EGL_BAD_MATCH";
    case EGL_BAD_NATIVE_PIXMAP:
      return "EGL_BAD_NATIVE_PIXMAP";
    case EGL_BAD_NATIVE_WINDOW:
      return "EGL_BAD_NATIVE_WINDOW";
    case EGL_BAD_PARAMETER:
      return "EGL_BAD_PARAMETER";
    case EGL_BAD_SURFACE:
      return "EGL_BAD_SURFACE";
    case EGL_CONTEXT_LOST:
      return "EGL_CONTEXT_LOST";
    case EGL_BAD_DEVICE_EXT:
      return "EGL_BAD_DEVICE_EXT";
  }
  char hex[16];
  std::snprintf(hex, sizeof hex, "0x%04X", static_cast<unsigned>(egl_error));
  return hex;
}

EglContext::EglContext() {
  const OpenedDisplay opened = open_display();
  display_ = opened.display;
  platform_ = opened.platform;
  try {
    create_context();
    make_current();
    read_gl_strings();
  } catch (...) {
    destroy();
    throw;
  }
}

EglContext::~EglContext() {
  destroy();
}

void EglContext::create_context() {
  const char* extensions = eglQueryString(display_, EGL_EXTENSIONS);
  if (!has_extension(extensions, "EGL_KHR_surfaceless_context")) {
    throw RenderError("EGL display (" + platform_ +
                      ") lacks EGL_KHR_surfaceless_context, needed to render without a surface");
  }
  if (!has_extension(extensions, "EGL_KHR_create_context")) {
    throw RenderError("EGL display (" + platform_ +
                      ") lacks EGL_KHR_create_context, needed to ask for a core profile");
  }
  if (eglBindAPI(EGL_OPENGL_API) != EGL_TRUE) {
    throw EglError("eglBindAPI(EGL_OPENGL_API)", eglGetError());
  }

  EGLConfig config = EGL_NO_CONFIG_KHR;
  if (!has_extension(extensions, "EGL_KHR_no_config_context")) {
    // No surface is ever created, so any surface type will do.
    const EGLint attributes[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, 0,
                                 EGL_NONE};
    EGLint count = 0;
    if (eglChooseConfig(display_, attributes, &config, 1, &count) != EGL_TRUE) {
      throw EglError("eglChooseConfig", eglGetError());
    }
    if (count == 0) throw RenderError("no EGL config of this display renders desktop OpenGL");
  }

  // 4.5 is what llvmpipe and current GPUs offer; the shaders need no more than 3.3.
  EGLint error = EGL_SUCCESS;
  for (const auto& [major, minor] : {std::pair{4, 5}, std::pair{3, 3}}) {
    const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                                 major,
                                 EGL_CONTEXT_MINOR_VERSION,
                                 minor,
                                 EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                 EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                 EGL_NONE};
    context_ = eglCreateContext(display_, config, EGL_NO_CONTEXT, attributes);
    if (context_ != EGL_NO_CONTEXT) return;
    error = eglGetError();
  }
  throw EglError("eglCreateContext", error, "OpenGL 4.5 or 3.3 core profile");
}

void EglContext::make_current() const {
  // The bound client API is per-thread state, and eglMakeCurrent acts on the bound API, so a
  // thread taking the context over must bind OpenGL first.
  if (eglBindAPI(EGL_OPENGL_API) != EGL_TRUE) {
    throw EglError("eglBindAPI(EGL_OPENGL_API)", eglGetError());
  }
  if (eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_) != EGL_TRUE) {
    throw EglError("eglMakeCurrent", eglGetError());
  }
}

void EglContext::release_current() const {
  if (context_ == nullptr || eglGetCurrentContext() != context_) return;
  eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
}

void EglContext::read_gl_strings() {
  const auto gl_string = [](GLenum name) {
    const GLubyte* value = glGetString(name);
    return value == nullptr ? std::string() : std::string(reinterpret_cast<const char*>(value));
  };
  renderer_ = gl_string(GL_RENDERER);
  version_ = gl_string(GL_VERSION);
  glGetIntegerv(GL_MAJOR_VERSION, &gl_major_);
  glGetIntegerv(GL_MINOR_VERSION, &gl_minor_);
}

void EglContext::destroy() noexcept {
  if (display_ == nullptr) return;
  release_current();
  // A context still current on another thread is deleted by EGL once that thread releases it.
  if (context_ != nullptr) eglDestroyContext(display_, context_);
  context_ = nullptr;
  release_display(display_);
  display_ = nullptr;
}

}  // namespace incise::render
