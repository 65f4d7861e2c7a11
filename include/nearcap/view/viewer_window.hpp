// nearcap/view/viewer_window.hpp — the viewer's window (GLFW): an OpenGL 4.5
// core context on a display, the keys and mouse as viewer commands, and a
// finished RGB frame shown as it is.
//
// The frame itself is drawn by render_lit_frame (render/lit_frame.hpp) in
// this window's context, into its own framebuffer object, exactly as the
// headless `nearcap render` draws it; the window then blits the finished
// picture (status line and crack overlay included) pixel for pixel into its
// default framebuffer.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "nearcap/judge/legend.hpp"
#include "nearcap/view/viewer_commands.hpp"

namespace nearcap::view {

class ViewerWindow {
 public:
  // Opens a width x height window (not resizable) and makes its context
  // current.  Throws Error(Gl) saying what is missing: no display (with the
  // xvfb-run line that gives one), no OpenGL 4.5 core context.
  ViewerWindow(int width, int height, const std::string& title);
  ~ViewerWindow();
  ViewerWindow(const ViewerWindow&) = delete;
  ViewerWindow& operator=(const ViewerWindow&) = delete;

  // Waits up to `seconds` for events (0: only what is queued); returns the
  // commands the keys and mouse drags gave since the last call, in order.
  std::vector<ViewerInput> poll(double seconds);
  bool closed() const;  // the window's close button, or Quit
  void set_title(const std::string& title);

  // Shows `image` (RGB, top row first, the window's size); with `screenshot`,
  // the window's pixels as drawn (read from the back buffer before the swap).
  void show(const legend::Image& image, legend::Image* screenshot = nullptr);

  std::string renderer() const;  // GL_RENDERER of the window's context

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace nearcap::view
