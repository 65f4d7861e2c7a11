// The viewer's window (see viewer_window.hpp).
#include "nearcap/view/viewer_window.hpp"

#include <epoxy/gl.h>
// GLFW after epoxy: epoxy declares GL itself.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <cstdint>

#include "nearcap/error.hpp"

namespace nearcap::view {
namespace {

std::string& last_glfw_error() {
  thread_local std::string message;
  return message;
}

void on_glfw_error(int code, const char* description) {
  last_glfw_error() = std::string(description ? description : "unknown") + " (GLFW error " + std::to_string(code) + ")";
}

// The keys of viewer_commands.hpp by GLFW key code.
const char* key_name(int key) {
  switch (key) {
    case GLFW_KEY_W:
      return "w";
    case GLFW_KEY_S:
      return "s";
    case GLFW_KEY_A:
      return "a";
    case GLFW_KEY_D:
      return "d";
    case GLFW_KEY_E:
      return "e";
    case GLFW_KEY_Q:
      return "q";
    case GLFW_KEY_LEFT:
      return "left";
    case GLFW_KEY_RIGHT:
      return "right";
    case GLFW_KEY_UP:
      return "up";
    case GLFW_KEY_DOWN:
      return "down";
    case GLFW_KEY_LEFT_BRACKET:
      return "[";
    case GLFW_KEY_RIGHT_BRACKET:
      return "]";
    case GLFW_KEY_M:
      return "m";
    case GLFW_KEY_N:
      return "n";
    case GLFW_KEY_L:
      return "l";
    case GLFW_KEY_C:
      return "c";
    case GLFW_KEY_H:
      return "h";
    case GLFW_KEY_P:
      return "p";
    case GLFW_KEY_ESCAPE:
      return "escape";
    case GLFW_KEY_1:
      return "1";
    case GLFW_KEY_2:
      return "2";
    case GLFW_KEY_3:
      return "3";
    case GLFW_KEY_4:
      return "4";
    case GLFW_KEY_5:
      return "5";
    case GLFW_KEY_6:
      return "6";
    case GLFW_KEY_7:
      return "7";
    case GLFW_KEY_8:
      return "8";
    case GLFW_KEY_9:
      return "9";
    default:
      return nullptr;
  }
}

constexpr double kDegreesPerPixel = 0.25, kDegreesPerTurn = 5.0;

}  // namespace

struct ViewerWindow::State {
  GLFWwindow* window = nullptr;
  int width = 0, height = 0;
  std::vector<ViewerInput> pending;
  bool dragging = false, quit = false;
  double last_x = 0, last_y = 0;
  GLuint texture = 0, read_framebuffer = 0;
};

ViewerWindow::ViewerWindow(int width, int height, const std::string& title) : state_(std::make_unique<State>()) {
  glfwSetErrorCallback(on_glfw_error);
  if (!glfwInit())
    throw Error(ErrorKind::Gl, "nearcap view needs a display, and GLFW found none: " + last_glfw_error() +
                                   " (on a machine without one: xvfb-run -a nearcap view ...)");
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_RESIZABLE, GLFW_FALSE);
  glfwWindowHint(GLFW_SAMPLES, 0);
  state_->window = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
  if (!state_->window) {
    const std::string why = last_glfw_error();
    glfwTerminate();
    throw Error(ErrorKind::Gl, "nearcap view could not open a window with an OpenGL 4.5 core context: " + why +
                                   " (the Mesa drivers: apt-get install libgl1-mesa-dri)");
  }
  state_->width = width;
  state_->height = height;
  glfwMakeContextCurrent(state_->window);
  glfwSwapInterval(0);
  glfwSetWindowUserPointer(state_->window, state_.get());
  glfwSetKeyCallback(state_->window, [](GLFWwindow* w, int key, int, int action, int) {
    auto* s = static_cast<State*>(glfwGetWindowUserPointer(w));
    if (action == GLFW_RELEASE) return;
    const char* name = key_name(key);
    ViewerInput input{};
    if (name && command_for_key(name, input)) s->pending.push_back(input);
  });
  glfwSetMouseButtonCallback(state_->window, [](GLFWwindow* w, int button, int action, int) {
    auto* s = static_cast<State*>(glfwGetWindowUserPointer(w));
    if (button != GLFW_MOUSE_BUTTON_LEFT) return;
    s->dragging = action == GLFW_PRESS;
    glfwGetCursorPos(w, &s->last_x, &s->last_y);
  });
  glfwSetCursorPosCallback(state_->window, [](GLFWwindow* w, double x, double y) {
    auto* s = static_cast<State*>(glfwGetWindowUserPointer(w));
    if (!s->dragging) return;
    const double dx = x - s->last_x, dy = y - s->last_y;
    s->last_x = x;
    s->last_y = y;
    // Dragging right turns right; dragging up looks up.
    if (dx != 0) s->pending.push_back({ViewerCommand::TurnRight, 0, dx * kDegreesPerPixel / kDegreesPerTurn});
    if (dy != 0) s->pending.push_back({ViewerCommand::TurnDown, 0, dy * kDegreesPerPixel / kDegreesPerTurn});
  });
  glGenTextures(1, &state_->texture);
  glBindTexture(GL_TEXTURE_2D, state_->texture);
  glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, width, height);
  glGenFramebuffers(1, &state_->read_framebuffer);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, state_->read_framebuffer);
  glFramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, state_->texture, 0);
  const bool complete = glCheckFramebufferStatus(GL_READ_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  if (!complete) {
    glDeleteFramebuffers(1, &state_->read_framebuffer);
    glDeleteTextures(1, &state_->texture);
    glfwDestroyWindow(state_->window);
    glfwTerminate();
    throw Error(ErrorKind::Gl, "the viewer's picture framebuffer is incomplete");
  }
}

ViewerWindow::~ViewerWindow() {
  if (state_->window) {
    glDeleteFramebuffers(1, &state_->read_framebuffer);
    glDeleteTextures(1, &state_->texture);
    glfwDestroyWindow(state_->window);
  }
  glfwTerminate();
}

std::vector<ViewerInput> ViewerWindow::poll(double seconds) {
  if (seconds > 0)
    glfwWaitEventsTimeout(seconds);
  else
    glfwPollEvents();
  std::vector<ViewerInput> out;
  out.swap(state_->pending);
  for (const ViewerInput& in : out)
    if (in.command == ViewerCommand::Quit) state_->quit = true;
  return out;
}

bool ViewerWindow::closed() const { return state_->quit || glfwWindowShouldClose(state_->window); }

void ViewerWindow::set_title(const std::string& title) { glfwSetWindowTitle(state_->window, title.c_str()); }

void ViewerWindow::show(const legend::Image& image, legend::Image* screenshot) {
  if (image.width != state_->width || image.height != state_->height)
    throw Error(ErrorKind::Usage, "the viewer's picture is not the window's size");
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glBindTexture(GL_TEXTURE_2D, state_->texture);
  glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, image.width, image.height, GL_RGB, GL_UNSIGNED_BYTE, image.rgb.data());
  int fb_width = 0, fb_height = 0;
  glfwGetFramebufferSize(state_->window, &fb_width, &fb_height);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, state_->read_framebuffer);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_FRAMEBUFFER_SRGB);
  // The texture's row 0 is the image's top row: flipped into GL's bottom-up window.
  glBlitFramebuffer(0, 0, image.width, image.height, 0, fb_height, fb_width, 0, GL_COLOR_BUFFER_BIT, GL_NEAREST);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  if (screenshot) {
    screenshot->width = fb_width;
    screenshot->height = fb_height;
    std::vector<std::uint8_t> rgba(static_cast<std::size_t>(fb_width) * fb_height * 4);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadBuffer(GL_BACK);
    glReadPixels(0, 0, fb_width, fb_height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    screenshot->rgb.resize(static_cast<std::size_t>(fb_width) * fb_height * 3);
    for (int j = 0; j < fb_height; ++j)
      for (int i = 0; i < fb_width; ++i)
        for (int c = 0; c < 3; ++c)
          screenshot->rgb[(static_cast<std::size_t>(fb_height - 1 - j) * fb_width + i) * 3 + c] =
              rgba[(static_cast<std::size_t>(j) * fb_width + i) * 4 + c];
  }
  glfwSwapBuffers(state_->window);
  const GLenum error = glGetError();
  if (error != GL_NO_ERROR)
    throw Error(ErrorKind::Gl, "showing the viewer's picture: GL error " + std::to_string(error));
}

std::string ViewerWindow::renderer() const {
  const auto* r = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  return r ? r : "unknown";
}

}  // namespace nearcap::view
