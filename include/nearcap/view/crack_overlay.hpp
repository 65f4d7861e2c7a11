// nearcap/view/crack_overlay.hpp — the viewer's crack overlay: the frame shown,
// judged against the exact reference in the background.
//
// A job is one shown frame: the scene as drawn (its camera), and per light
// drawn the emulated frame with the real GL's stencil in place of the
// emulation's (the lit frame's stencils, render_lit_frame(..., true)).  The
// worker computes each light's exact reference (pixel_reference.hpp), judges
// the frame (crack_map.hpp: the visible objects are the emulation's depth
// pre-pass, which the replay tests find equal to the real GL's on the bundled
// scenes) and measures the crack distances (crack_distances.hpp), so that a
// wrong pixel is marked a crack or boundary noise like `nearcap cracks`
// marks it.  One job runs at a time; a job started while one runs waits,
// replacing any job waiting before it (the camera moved on).
#pragma once

#include <cstdint>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "nearcap/gl/shadow_methods.hpp"
#include "nearcap/judge/legend.hpp"
#include "nearcap/scene/scene.hpp"

namespace nearcap::view {

enum class OverlayMark : std::uint8_t { None, NoiseLit, NoiseShadowed, CrackLit, CrackShadowed };

struct CrackOverlayJob {
  std::uint64_t frame_id = 0;  // the viewer's frame counter: which frame this judges
  Scene scene;
  std::vector<gl::ShadowFrame> frames;  // per light drawn; stencil as drawn; no draws needed
};

struct CrackOverlayResult {
  std::uint64_t frame_id = 0;
  std::size_t wrong = 0;           // wrong pixels, every light drawn (a pixel wrong for two lights counts twice)
  std::size_t cracks = 0;          // among them, cracks (crack distance level >= kCrackLevel)
  std::vector<OverlayMark> marks;  // per pixel, row 0 at the bottom: the worst mark over the lights
  double ms = 0;                   // the worker's time for this job
  std::string error;               // what the exact kernel refused, or ""
};

// Judges one job in the calling thread.
CrackOverlayResult judge_overlay_job(const CrackOverlayJob& job);

// The marks painted over `image` (RGB, top row first, the frame's size), each
// at 70 % over the frame: cracks red (lit, should be shadowed) and cyan
// (shadowed, should be lit) with a ring of radius 5 pixels around each (on
// unmarked pixels), boundary noise orange and blue without a ring.
void paint_overlay(legend::Image& image, const CrackOverlayResult& result);

class CrackOverlay {
 public:
  ~CrackOverlay();
  void start(CrackOverlayJob job);
  // The newest finished result, if one finished since the last call; starts
  // the waiting job when the worker is free.
  std::optional<CrackOverlayResult> poll();
  // Blocks until the worker is idle and nothing waits; the last result.
  std::optional<CrackOverlayResult> wait();
  bool busy() const { return running_.valid() || waiting_ != nullptr; }

 private:
  std::future<CrackOverlayResult> running_;
  std::unique_ptr<CrackOverlayJob> waiting_;
};

}  // namespace nearcap::view
