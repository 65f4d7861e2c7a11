// Float frames judged against the exact reference (see crack_map.hpp).
#include "nearcap/judge/crack_map.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "nearcap/check.hpp"
#include "nearcap/io/image_io.hpp"
#include "nearcap/judge/legend.hpp"
#include "nearcap/judge/reference_images.hpp"
#include "nearcap/raytrace/shadow_ray_tracer.hpp"

namespace nearcap {

namespace {

// What a frame's per-pixel byte says: a stencil value (compared with the
// reference's count mod 256) or a shadow status alone (ray tracing: no
// count, so a pixel's count differs exactly where its status does).
enum class FrameByte { StencilCount, ShadowStatus };

// The judgement both frame kinds share (crack_map.hpp).  `object` and
// `shadow` are the frame's per-pixel visible object and byte, row 0 at the
// bottom, ref.width x ref.height.
CrackReport judge_pixels(std::string method, const std::vector<std::int32_t>& object,
                         const std::vector<std::uint8_t>& shadow, FrameByte byte, const PixelReference& ref) {
  CrackReport r;
  r.method = std::move(method);
  const std::size_t n = static_cast<std::size_t>(ref.width) * ref.height;
  r.verdict.assign(n, PixelVerdict::NothingSeen);
  for (std::size_t p = 0; p < n; ++p) {
    const bool seen = ref.stencil[p] != PixelReference::kNothingSeen;
    if (seen) ++r.pixels_seen;
    if (ref.object[p] != object[p]) {
      r.verdict[p] = PixelVerdict::VisibilityMismatch;
      ++r.visibility_mismatch;
      continue;
    }
    if (!seen) continue;
    const bool ref_shadowed = ref.stencil[p] > 0, frame_shadowed = shadow[p] != 0;
    const bool count_differs = byte == FrameByte::StencilCount
                                   ? shadow[p] != static_cast<std::uint8_t>(ref.stencil[p] & 0xffu)
                                   : ref_shadowed != frame_shadowed;
    PixelVerdict v = PixelVerdict::Right;
    if (ref_shadowed && !frame_shadowed)
      v = PixelVerdict::WrongLit;
    else if (!ref_shadowed && frame_shadowed)
      v = PixelVerdict::WrongShadowed;
    else if (count_differs)
      v = PixelVerdict::CountOnly;
    r.verdict[p] = v;
    if (v == PixelVerdict::WrongLit) ++r.wrong_lit;
    if (v == PixelVerdict::WrongShadowed) ++r.wrong_shadowed;
    if (count_differs) ++r.count_mismatch;
  }
  r.wrong = r.wrong_lit + r.wrong_shadowed;
  return r;
}

}  // namespace

CrackReport judge_frame(const gl::ShadowFrame& frame, const PixelReference& ref) {
  NEARCAP_CHECK(frame.width == ref.width && frame.height == ref.height);
  CrackReport r =
      judge_pixels(std::string(to_string(frame.method)), frame.object, frame.stencil, FrameByte::StencilCount, ref);
  if (!frame.near_cap.empty() && frame.zfail_objects.empty() && !frame.near_moved) {
    const std::size_t n = r.verdict.size();
    r.cap_wrong.assign(n, false);
    std::size_t mismatches = 0;
    for (std::size_t p = 0; p < n; ++p)
      if (frame.near_cap[p] != static_cast<std::uint8_t>(ref.cap[p] & 0xffu)) {
        r.cap_wrong[p] = true;
        ++mismatches;
      }
    r.cap_mismatch = mismatches;
  }
  return r;
}

CrackReport judge_raytrace_frame(const raytrace::RaytraceFrame& frame, const PixelReference& ref) {
  NEARCAP_CHECK(frame.width == ref.width && frame.height == ref.height);
  return judge_pixels("raytrace", frame.object, frame.shadowed, FrameByte::ShadowStatus, ref);
}

namespace {

using Rgb = legend::Rgb;

constexpr Rgb kWrongLit{255, 40, 40}, kWrongShadowed{40, 230, 255}, kCountOnly{255, 220, 0}, kCapWrong{255, 0, 255},
    kVisibility{110, 110, 110}, kNoiseLit{255, 150, 40}, kNoiseShadowed{70, 110, 255};

// A wrong pixel whose crack distance was measured below kCrackLevel.
bool is_noise(const CrackReport& report, std::size_t p) {
  return !report.distance.empty() && report.distance[p] >= 0 && report.distance[p] < kCrackLevel;
}

// The fill of a judged pixel (crack_map.hpp), nothing when it is right.  The
// verdict decides; a near-cap mismatch fills only a pixel whose verdict is
// right (else it shows as the outer ring).
std::optional<Rgb> mark_colour(const CrackReport& report, std::size_t p) {
  switch (report.verdict[p]) {
    case PixelVerdict::WrongLit:
      return is_noise(report, p) ? kNoiseLit : kWrongLit;
    case PixelVerdict::WrongShadowed:
      return is_noise(report, p) ? kNoiseShadowed : kWrongShadowed;
    case PixelVerdict::CountOnly:
      return kCountOnly;
    case PixelVerdict::VisibilityMismatch:
      return kVisibility;
    default:
      if (!report.cap_wrong.empty() && report.cap_wrong[p]) return kCapWrong;
      return std::nullopt;
  }
}

// The verdict's ring colour, drawn in increasing priority; nothing for right pixels.
int ring_priority(PixelVerdict v) {
  switch (v) {
    case PixelVerdict::VisibilityMismatch:
      return 1;
    case PixelVerdict::CountOnly:
      return 2;
    case PixelVerdict::WrongShadowed:
      return 3;
    case PixelVerdict::WrongLit:
      return 4;
    default:
      return 0;
  }
}

}  // namespace

std::string crack_png(const CameraSpaceScene& scene, const PixelReference& ref, const CrackReport& report) {
  std::vector<std::uint8_t> rgb = shadow_rgb(scene, ref);
  auto pixel = [&](int i, int j) { return &rgb[3 * (static_cast<std::size_t>(ref.height - 1 - j) * ref.width + i)]; };
  std::vector<bool> marked(static_cast<std::size_t>(ref.width) * ref.height, false);
  for (int j = 0; j < ref.height; ++j)
    for (int i = 0; i < ref.width; ++i) {
      std::uint8_t* px = pixel(i, j);
      if (const auto mark = mark_colour(report, ref.index(i, j))) {
        for (int c = 0; c < 3; ++c) px[c] = (*mark)[c];
        marked[ref.index(i, j)] = true;
      } else {
        for (int c = 0; c < 3; ++c) px[c] = static_cast<std::uint8_t>(px[c] / 2);  // dim what is right
      }
    }
  // Cracks are often single pixels: every marked pixel is ringed so that a
  // person finds it at once.  Inner rings (radius 5) in the verdict's colour,
  // drawn by priority (visibility, count-only, wrong-shadowed, wrong-lit: the
  // worst on top); outer rings (radius 7) in magenta for near-cap mismatches,
  // so a pixel that is both wrong and a near-cap mismatch shows both.  Rings
  // never paint over a marked pixel, so no mark hides another.
  auto ring = [&](int i, int j, int r, const Rgb& colour) {
    for (int dj = -r; dj <= r; ++dj)
      for (int di = -r; di <= r; ++di) {
        if (std::max(std::abs(di), std::abs(dj)) != r) continue;
        const int x = i + di, y = j + dj;
        if (x < 0 || y < 0 || x >= ref.width || y >= ref.height || marked[ref.index(x, y)]) continue;
        std::uint8_t* q = pixel(x, y);
        for (int c = 0; c < 3; ++c) q[c] = colour[c];
      }
  };
  for (int priority = 1; priority <= 4; ++priority)
    for (int j = 0; j < ref.height; ++j)
      for (int i = 0; i < ref.width; ++i) {
        const std::size_t p = ref.index(i, j);
        if (ring_priority(report.verdict[p]) == priority && !is_noise(report, p))
          ring(i, j, 5, *mark_colour(report, p));
      }
  if (!report.cap_wrong.empty())
    for (int j = 0; j < ref.height; ++j)
      for (int i = 0; i < ref.width; ++i)
        if (report.cap_wrong[ref.index(i, j)]) ring(i, j, 7, kCapWrong);

  const std::string title =
      report.method + ": " + std::to_string(report.wrong) + " wrong (" + std::to_string(report.wrong_lit) + " lit, " +
      std::to_string(report.wrong_shadowed) + " shadowed), " +
      (report.cracks ? std::to_string(*report.cracks) + " cracks, " : std::string()) +
      std::to_string(report.count_mismatch) + " count, " +
      (report.cap_mismatch ? std::to_string(*report.cap_mismatch) : std::string("-")) + " near-cap";
  std::vector<legend::Entry> entries;
  if (report.cracks) {
    entries = {{kWrongLit, "crack, lit: should be in shadow"},
               {kWrongShadowed, "crack, shadowed: should be lit"},
               {kNoiseLit, "boundary noise, lit (exact status not constant over the pixel)"},
               {kNoiseShadowed, "boundary noise, shadowed"}};
  } else {
    entries = {{kWrongLit, "wrong, lit: should be in shadow"}, {kWrongShadowed, "wrong, shadowed: should be lit"}};
  }
  entries.insert(entries.end(), {{kCountOnly, "stencil count differs, status right"},
                                 {kCapWrong, "near-cap pass differs (outer ring)"},
                                 {kVisibility, "another object seen (outline)"}});
  const legend::Image framed = legend::with_legend({ref.width, ref.height, std::move(rgb)}, title, entries);
  return png_with_text(encode_png_rgb(framed.width, framed.height, framed.rgb), "Title", title);
}

}  // namespace nearcap
