// nearcap/judge/crack_map.hpp — a float pipeline's stencil buffer judged pixel by
// pixel against the exact reference: the crack pixels.
//
// Per pixel (i, j), with ref the exact reference (pixel_reference.hpp) and
// frame the emulated method (gl/shadow_methods.hpp):
//   NothingSeen         neither sees a surface;
//   VisibilityMismatch  they see different objects (or one sees nothing): the
//                       depth pre-pass's snapped coverage differs from the exact
//                       centre sample at an object's outline.  Not a shadow
//                       crack; counted apart and excluded from the rest;
//   WrongLit            frame lit (stencil 0), reference shadowed (count > 0);
//   WrongShadowed       frame shadowed, reference lit;
//   CountOnly           same shadow status, but stencil != count mod 256;
//   Right               stencil == count mod 256.
// A method's near-cap pass (ZP+) is compared with the reference's cap count
// (mod 256) on every pixel of the viewport: cap_mismatch.  When a method left
// occluders out of its near-cap pass (zpplus-corrected's switch to Z-fail for
// a case-D occluder), or drew with another near plane than the scene's
// (gl::NearPlane::Tight), its cap is not the reference's, and cap_mismatch
// is not reported.
//
// A ray-traced frame (raytrace/shadow_ray_tracer.hpp) has a shadow status per
// pixel and no count: it is judged by status alone (judge_raytrace_frame), so
// CountOnly never occurs and count_mismatch equals wrong.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "nearcap/exact/camera_space.hpp"
#include "nearcap/exact/crack_distance.hpp"
#include "nearcap/exact/pixel_reference.hpp"
#include "nearcap/gl/shadow_methods.hpp"

namespace nearcap {

namespace raytrace {
struct RaytraceFrame;  // raytrace/shadow_ray_tracer.hpp, in the nearcap::raytrace library
}

enum class PixelVerdict : std::uint8_t { NothingSeen, Right, CountOnly, WrongLit, WrongShadowed, VisibilityMismatch };

struct CrackReport {
  std::string method;                       // "zpass", ..., "raytrace": the name the legend shows
  std::size_t pixels_seen = 0;              // the reference sees a surface
  std::size_t wrong = 0;                    // wrong_lit + wrong_shadowed
  std::size_t wrong_lit = 0;                // lit, should be shadowed
  std::size_t wrong_shadowed = 0;           // shadowed, should be lit
  std::size_t count_mismatch = 0;           // stencil != exact count (mod 256), wrong pixels included
  std::optional<std::size_t> cap_mismatch;  // ZP+ methods with a whole-scene cap pass
  std::size_t visibility_mismatch = 0;
  std::vector<PixelVerdict> verdict;  // row 0 at the bottom
  std::vector<bool> cap_wrong;        // per pixel, when cap_mismatch is reported
  // Filled by CrackDistances::measure (crack_distances.hpp), empty before:
  // the wrong pixels per crack-distance level (exact/crack_distance.hpp), the
  // cracks among them (level >= kCrackLevel), and each pixel's level (-1 for
  // a pixel that is not wrong).
  std::optional<std::array<std::size_t, kCrackDistanceLevels>> wrong_by_distance;
  std::optional<std::size_t> cracks;
  std::vector<std::int8_t> distance;
};

CrackReport judge_frame(const gl::ShadowFrame& frame, const PixelReference& ref);
CrackReport judge_raytrace_frame(const raytrace::RaytraceFrame& frame, const PixelReference& ref);

// The reference's shaded image (reference_images.hpp), dimmed, with each
// judged pixel filled by its verdict: wrong-lit red, wrong-shadowed cyan,
// count-only yellow, visibility mismatch grey; a near-cap mismatch fills a
// pixel magenta when its verdict is right.  When the crack distances were
// measured, a wrong pixel that is boundary noise (not a crack) is filled
// orange (lit) or blue (shadowed) and not ringed.  Every other marked pixel is ringed: an
// inner square (11 pixels wide) in its verdict's colour, rings of worse
// verdicts drawn over milder ones (grey, yellow, cyan, red), and an outer
// magenta square (15 wide) around each near-cap mismatch; rings never cover a
// marked pixel.  Below the image, a legend: report.method (the name shown:
// for a policy's frame, "policy" and the methods it ran), its counts and the
// colours, wrapped to the frame's width (legend::with_legend: one PNG width
// per frame width).  8-bit RGB PNG bytes.
std::string crack_png(const CameraSpaceScene& scene, const PixelReference& ref, const CrackReport& report);

}  // namespace nearcap
