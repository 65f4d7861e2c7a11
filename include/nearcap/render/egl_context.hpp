// nearcap/render/egl_context.hpp — a headless OpenGL 4.5 core context.
//
// The real-GL side of nearcap (the renderer, the probes that check the
// emulation against a real rasterizer) draws into framebuffer objects of a
// context with no window: EGL on Mesa's surfaceless platform (llvmpipe on a
// machine without a GPU), or, where that is missing, EGL's device platform
// (a GPU driver's EGL).  Everything GL is loaded through libepoxy.
#pragma once

#include <memory>
#include <string>

namespace nearcap::render {

class EglContext {
 public:
  // Creates the context and makes it current on the calling thread.  Throws
  // nearcap::Error(ErrorKind::Gl) saying which EGL step failed.
  EglContext();
  ~EglContext();
  EglContext(const EglContext&) = delete;
  EglContext& operator=(const EglContext&) = delete;

  std::string renderer() const;  // GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
  std::string version() const;   // GL_VERSION
  std::string platform() const;  // "surfaceless" or "device"

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace nearcap::render
