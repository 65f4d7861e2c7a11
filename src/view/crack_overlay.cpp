// The viewer's crack overlay (see crack_overlay.hpp).
#include "nearcap/view/crack_overlay.hpp"

#include <algorithm>
#include <chrono>

#include "nearcap/error.hpp"
#include "nearcap/exact/camera_space.hpp"
#include "nearcap/exact/crack_distance.hpp"
#include "nearcap/exact/pixel_reference.hpp"
#include "nearcap/judge/crack_distances.hpp"
#include "nearcap/judge/crack_map.hpp"

namespace nearcap::view {

CrackOverlayResult judge_overlay_job(const CrackOverlayJob& job) {
  const auto t0 = std::chrono::steady_clock::now();
  CrackOverlayResult out;
  out.frame_id = job.frame_id;
  const std::size_t pixels = static_cast<std::size_t>(job.scene.camera.width) * job.scene.camera.height;
  out.marks.assign(pixels, OverlayMark::None);
  try {
    const CameraSpaceScene cs(job.scene);
    for (const gl::ShadowFrame& frame : job.frames) {
      const PixelReferenceTracer tracer(cs, frame.light);
      const PixelReference ref = compute_pixel_reference(tracer);
      CrackReport report = judge_frame(frame, ref);
      CrackDistances distances(tracer, ref);
      distances.measure(report);
      out.wrong += report.wrong;
      out.cracks += report.cracks.value_or(0);
      for (std::size_t p = 0; p < pixels && p < report.verdict.size(); ++p) {
        const PixelVerdict v = report.verdict[p];
        if (v != PixelVerdict::WrongLit && v != PixelVerdict::WrongShadowed) continue;
        const bool crack = report.distance.empty() || report.distance[p] >= kCrackLevel;
        const bool lit = v == PixelVerdict::WrongLit;
        const OverlayMark m = crack ? (lit ? OverlayMark::CrackLit : OverlayMark::CrackShadowed)
                                    : (lit ? OverlayMark::NoiseLit : OverlayMark::NoiseShadowed);
        out.marks[p] = std::max(out.marks[p], m);
      }
    }
  } catch (const std::exception& e) {  // nearcap::Error, or running out of memory: the viewer goes on
    out.error = e.what();
  }
  out.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

void paint_overlay(legend::Image& image, const CrackOverlayResult& result) {
  const int w = image.width, h = image.height;
  if (result.marks.size() != static_cast<std::size_t>(w) * h) return;
  auto colour = [](OverlayMark m) -> legend::Rgb {
    switch (m) {
      case OverlayMark::CrackLit:
        return {230, 20, 20};
      case OverlayMark::CrackShadowed:
        return {0, 220, 230};
      case OverlayMark::NoiseLit:
        return {255, 150, 0};
      case OverlayMark::NoiseShadowed:
        return {40, 80, 255};
      case OverlayMark::None:
        break;
    }
    return {0, 0, 0};
  };
  auto set = [&](int i, int row_from_top, const legend::Rgb& c) {
    if (i < 0 || i >= w || row_from_top < 0 || row_from_top >= h) return;
    if (result.marks[static_cast<std::size_t>(h - 1 - row_from_top) * w + i] != OverlayMark::None) return;
    std::copy(c.begin(), c.end(), &image.rgb[3 * (static_cast<std::size_t>(row_from_top) * w + i)]);
  };
  constexpr int kRing = 5;
  // Rings first, on unmarked pixels only (a ring never hides a mark).
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const OverlayMark m = result.marks[static_cast<std::size_t>(j) * w + i];
      if (m != OverlayMark::CrackLit && m != OverlayMark::CrackShadowed) continue;
      const int top = h - 1 - j;
      for (int d = -kRing; d <= kRing; ++d) {
        set(i + d, top - kRing, colour(m));
        set(i + d, top + kRing, colour(m));
        set(i - kRing, top + d, colour(m));
        set(i + kRing, top + d, colour(m));
      }
    }
  // A marked pixel: its colour over the frame at 70 %, so the scene shows through.
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const OverlayMark m = result.marks[static_cast<std::size_t>(j) * w + i];
      if (m == OverlayMark::None) continue;
      const legend::Rgb c = colour(m);
      std::uint8_t* p = &image.rgb[3 * (static_cast<std::size_t>(h - 1 - j) * w + i)];
      for (int k = 0; k < 3; ++k) p[k] = static_cast<std::uint8_t>((3 * p[k] + 7 * c[k] + 5) / 10);
    }
}

CrackOverlay::~CrackOverlay() {
  if (running_.valid()) running_.wait();
}

void CrackOverlay::start(CrackOverlayJob job) {
  waiting_ = std::make_unique<CrackOverlayJob>(std::move(job));
  if (!running_.valid()) {
    std::shared_ptr<CrackOverlayJob> next(waiting_.release());
    running_ = std::async(std::launch::async, [next] { return judge_overlay_job(*next); });
  }
}

std::optional<CrackOverlayResult> CrackOverlay::poll() {
  std::optional<CrackOverlayResult> out;
  if (running_.valid() && running_.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
    out = running_.get();
    if (waiting_) {
      std::shared_ptr<CrackOverlayJob> next(waiting_.release());
      running_ = std::async(std::launch::async, [next] { return judge_overlay_job(*next); });
    }
  }
  return out;
}

std::optional<CrackOverlayResult> CrackOverlay::wait() {
  std::optional<CrackOverlayResult> last;
  while (running_.valid()) {
    running_.wait();
    if (auto r = poll()) last = std::move(r);
  }
  return last;
}

}  // namespace nearcap::view
