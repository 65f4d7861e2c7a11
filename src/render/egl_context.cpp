// A headless OpenGL 4.5 core context through EGL (see egl_context.hpp).
#include "nearcap/render/egl_context.hpp"

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <cstring>
#include <string>
#include <vector>

#include "nearcap/error.hpp"

namespace nearcap::render {

struct EglContext::State {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
  std::string platform;
};

namespace {

[[noreturn]] void egl_fail(const std::string& step) {
  char code[16];
  std::snprintf(code, sizeof code, "0x%04X", static_cast<unsigned>(eglGetError()));
  throw Error(ErrorKind::Gl, "EGL: " + step + " failed (EGL error " + code + ")");
}

bool has_extension(const char* list, const char* name) {
  if (list == nullptr) return false;
  const std::size_t n = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += n)
    if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
  return false;
}

// An initialized display: Mesa's surfaceless platform first (no window system,
// no GPU needed), then the first EGL device that initializes.
EGLDisplay open_display(std::string& platform) {
  // Client extensions; eglGetPlatformDisplayEXT (not eglGetPlatformDisplay:
  // through libepoxy that aborts before a display exists).
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (!has_extension(client, "EGL_EXT_platform_base"))
    throw Error(ErrorKind::Gl,
                "EGL: the client library lacks EGL_EXT_platform_base (no headless EGL: no EGL driver was found; "
                "install libegl1-mesa-dev and libgl1-mesa-dri, as scripts/install-deps.sh does)");
  EGLint major = 0, minor = 0;
  if (has_extension(client, "EGL_MESA_platform_surfaceless")) {
    EGLDisplay d = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (d != EGL_NO_DISPLAY && eglInitialize(d, &major, &minor)) {
      platform = "surfaceless";
      return d;
    }
  }
  if (has_extension(client, "EGL_EXT_platform_device") && has_extension(client, "EGL_EXT_device_enumeration")) {
    EGLint count = 0;
    if (!eglQueryDevicesEXT(0, nullptr, &count) || count <= 0) egl_fail("eglQueryDevicesEXT (no EGL device)");
    std::vector<EGLDeviceEXT> devices(static_cast<std::size_t>(count));
    eglQueryDevicesEXT(count, devices.data(), &count);
    for (EGLDeviceEXT device : devices) {
      EGLDisplay d = eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, device, nullptr);
      if (d != EGL_NO_DISPLAY && eglInitialize(d, &major, &minor)) {
        platform = "device";
        return d;
      }
    }
  }
  throw Error(ErrorKind::Gl,
              "EGL: neither the surfaceless platform (Mesa) nor an EGL device could be initialized "
              "(install libegl1-mesa-dev and libgl1-mesa-dri, or a GPU driver with EGL)");
}

}  // namespace

EglContext::EglContext() : state_(std::make_unique<State>()) {
  state_->display = open_display(state_->platform);
  try {
    if (!eglBindAPI(EGL_OPENGL_API)) egl_fail("eglBindAPI(EGL_OPENGL_API)");
    const char* display_extensions = eglQueryString(state_->display, EGL_EXTENSIONS);
    if (!has_extension(display_extensions, "EGL_KHR_surfaceless_context"))
      throw Error(ErrorKind::Gl, "EGL: the display lacks EGL_KHR_surfaceless_context");
    EGLConfig config = EGL_NO_CONFIG_KHR;
    if (!has_extension(display_extensions, "EGL_KHR_no_config_context")) {
      const EGLint attributes[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
      EGLint n = 0;
      if (!eglChooseConfig(state_->display, attributes, &config, 1, &n) || n < 1) egl_fail("eglChooseConfig");
    }
    const EGLint context_attributes[] = {
        EGL_CONTEXT_MAJOR_VERSION,           4,       EGL_CONTEXT_MINOR_VERSION, 5, EGL_CONTEXT_OPENGL_PROFILE_MASK,
        EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    state_->context = eglCreateContext(state_->display, config, EGL_NO_CONTEXT, context_attributes);
    if (state_->context == EGL_NO_CONTEXT) egl_fail("eglCreateContext (OpenGL 4.5 core)");
    if (!eglMakeCurrent(state_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, state_->context)) egl_fail("eglMakeCurrent");
  } catch (...) {
    if (state_->context != EGL_NO_CONTEXT) eglDestroyContext(state_->display, state_->context);
    eglTerminate(state_->display);
    throw;
  }
}

EglContext::~EglContext() {
  eglMakeCurrent(state_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(state_->display, state_->context);
  eglTerminate(state_->display);
}

std::string EglContext::renderer() const { return reinterpret_cast<const char*>(glGetString(GL_RENDERER)); }
std::string EglContext::version() const { return reinterpret_cast<const char*>(glGetString(GL_VERSION)); }
std::string EglContext::platform() const { return state_->platform; }

}  // namespace nearcap::render
