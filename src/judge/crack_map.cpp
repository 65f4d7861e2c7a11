// Float frames judged against the exact reference (see crack_map.hpp).
#include "nearcap/judge/crack_map.hpp"

#include <algorithm>
#include <array>
#include <cstdlib>

#include "nearcap/check.hpp"
#include "nearcap/io/image_io.hpp"
#include "nearcap/judge/reference_images.hpp"

namespace nearcap {

CrackReport judge_frame(const gl::ShadowFrame& frame, const PixelReference& ref) {
  NEARCAP_CHECK(frame.width == ref.width && frame.height == ref.height);
  CrackReport r;
  r.method = frame.method;
  const std::size_t n = static_cast<std::size_t>(ref.width) * ref.height;
  r.verdict.assign(n, PixelVerdict::NothingSeen);
  for (std::size_t p = 0; p < n; ++p) {
    const bool seen = ref.stencil[p] != PixelReference::kNothingSeen;
    if (seen) ++r.pixels_seen;
    if (ref.object[p] != frame.object[p]) {
      r.verdict[p] = PixelVerdict::VisibilityMismatch;
      ++r.visibility_mismatch;
      continue;
    }
    if (!seen) continue;
    const std::uint8_t exact = static_cast<std::uint8_t>(ref.stencil[p] & 0xffu);
    const bool ref_shadowed = ref.stencil[p] > 0, frame_shadowed = frame.stencil[p] != 0;
    PixelVerdict v = PixelVerdict::Right;
    if (ref_shadowed && !frame_shadowed)
      v = PixelVerdict::WrongLit;
    else if (!ref_shadowed && frame_shadowed)
      v = PixelVerdict::WrongShadowed;
    else if (frame.stencil[p] != exact)
      v = PixelVerdict::CountOnly;
    r.verdict[p] = v;
    if (v == PixelVerdict::WrongLit) ++r.wrong_lit;
    if (v == PixelVerdict::WrongShadowed) ++r.wrong_shadowed;
    if (frame.stencil[p] != exact) ++r.count_mismatch;
  }
  r.wrong = r.wrong_lit + r.wrong_shadowed;
  if (!frame.near_cap.empty() && frame.zfail_objects.empty()) {
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

namespace {

using Rgb = std::array<std::uint8_t, 3>;

// The mark of a judged pixel (crack_map.hpp), nothing when it is right.
std::optional<Rgb> mark_colour(const CrackReport& report, std::size_t p) {
  switch (report.verdict[p]) {
    case PixelVerdict::WrongLit:
      return Rgb{255, 40, 40};
    case PixelVerdict::WrongShadowed:
      return Rgb{40, 230, 255};
    case PixelVerdict::CountOnly:
      return Rgb{255, 220, 0};
    case PixelVerdict::VisibilityMismatch:
      return Rgb{70, 70, 70};
    default:
      if (!report.cap_wrong.empty() && report.cap_wrong[p]) return Rgb{255, 0, 255};
      return std::nullopt;
  }
}

bool ringed(const CrackReport& report, std::size_t p) {
  const PixelVerdict v = report.verdict[p];
  return v == PixelVerdict::WrongLit || v == PixelVerdict::WrongShadowed ||
         (!report.cap_wrong.empty() && report.cap_wrong[p]);
}

}  // namespace

std::string crack_png(const CameraSpaceScene& scene, const PixelReference& ref, const CrackReport& report) {
  std::vector<std::uint8_t> rgb = shadow_rgb(scene, ref);
  auto pixel = [&](int i, int j) { return &rgb[3 * (static_cast<std::size_t>(ref.height - 1 - j) * ref.width + i)]; };
  for (int j = 0; j < ref.height; ++j)
    for (int i = 0; i < ref.width; ++i) {
      std::uint8_t* px = pixel(i, j);
      if (const auto mark = mark_colour(report, ref.index(i, j))) {
        for (int c = 0; c < 3; ++c) px[c] = (*mark)[c];
      } else {
        for (int c = 0; c < 3; ++c) px[c] = static_cast<std::uint8_t>(px[c] / 2);  // dim what is right
      }
    }
  // Cracks are often single pixels: ring each wrong pixel (and each near-cap
  // mismatch) with a square of its colour so that a person finds it at once.
  const int r = 6;
  for (int j = 0; j < ref.height; ++j)
    for (int i = 0; i < ref.width; ++i) {
      const std::size_t p = ref.index(i, j);
      if (!ringed(report, p)) continue;
      const Rgb colour = *mark_colour(report, p);
      for (int dj = -r; dj <= r; ++dj)
        for (int di = -r; di <= r; ++di) {
          if (std::max(std::abs(di), std::abs(dj)) != r) continue;
          const int x = i + di, y = j + dj;
          if (x < 0 || y < 0 || x >= ref.width || y >= ref.height) continue;
          std::uint8_t* q = pixel(x, y);
          for (int c = 0; c < 3; ++c) q[c] = colour[c];
        }
    }
  return encode_png_rgb(ref.width, ref.height, rgb);
}

}  // namespace nearcap
