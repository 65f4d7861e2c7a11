// nearcap/exact/pixel_reference.hpp — the exact per-pixel reference: what the
// stencil buffer should hold.
//
// For light l and pixel (i, j) (column i from the left, row j from the bottom;
// its centre p is the camera-space near-plane point of pixel_centre()):
//   cap(i, j)     = number of light-front-facing occluder triangles crossed by
//                   the segment [l, p]: the near-cap count ZP+ should render;
//   stencil(i, j) = with q the first surface point seen through p (beyond the
//                   near plane, before the far plane; occluders and receivers
//                   alike), the number of light-front-facing occluder triangles
//                   crossed by the segment from l to q-, the point just before q
//                   on the view ray: the number of shadow volumes q- lies in.
//                   So q's own triangle counts exactly when the eye sees it from
//                   behind (the camera inside an occluder looking at the inner
//                   side of a lit face: the inside of an opaque body is dark, and
//                   every stencil method counts it so).  The pixel is in shadow
//                   when stencil > 0.
//
// Degeneracies: p is perturbed symbolically (perturbation.hpp: first away from
// the camera, then +x, then +y), and every test below is the sign of an affine
// form in p, so a pixel centre on a projected edge, on a silhouette, on the
// near or far plane is decided by that one rule.  What the perturbation cannot
// separate is a property of the scene, with its own rule:
//   - a triangle whose plane passes through the eye is never seen (edge-on);
//   - two coplanar triangles both hit: the lower (object, face) index is seen;
//   - a triangle coplanar with q's triangle is never crossed by (l, q);
//   - a triangle exactly in the near plane is beyond it (seen), as GL's
//     closed clip volume keeps it, where the perturbation would not.
//
// The forms (camera space, n = (b-a) x (c-a), d = det(a, b, c) for triangle
// abc, all as functions of the sample point P):
//   ray hits abc          sign(P.(a x b)) = sign(P.(b x c)) = sign(P.(c x a)) = sign(d)
//   hit beyond p          sign(d - n.P) = sign(d)               (t = d / n.P > 1)
//   hit before far        sign(far n.P - near d) = sign(d)
//   hit 1 before hit 2    sign(d1 d2) sign((d1 n2 - d2 n1).P) < 0
//   q beyond T's plane    sign(d_q) sign((d_q n_T - d_T n_q).P) = -(light's side)
//   (l, q) inside T       sign((d_q g_k + g0_k n_q).P) equal for k = 0, 1, 2,
//                         with g_k = (u-l) x (v-l), g0_k = -g_k.l for T's edges uv.
// Each is evaluated in BoundedDouble and recomputed over rationals only when
// the filter cannot decide (FilterStats counts both).  A cube-map grid around
// the eye and one around the light (central_grid.hpp) supply the candidates.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include "nearcap/exact/camera_space.hpp"
#include "nearcap/exact/central_grid.hpp"
#include "nearcap/exact/eye_setup.hpp"
#include "nearcap/exact/light_setup.hpp"
#include "nearcap/exact/segment_crossing.hpp"
#include "nearcap/numeric/filter_stats.hpp"
#include "nearcap/numeric/sign.hpp"

namespace nearcap {

// A few object indices without a heap allocation (the objects a pixel's
// near-cap segment crosses: one or two in practice), more on the heap.
class SmallObjectSet {
 public:
  void insert(std::uint32_t o) {
    for (std::size_t k = 0; k < size(); ++k)
      if ((*this)[k] == o) return;
    if (inline_count_ < inline_.size())
      inline_[inline_count_++] = o;
    else
      more_.push_back(o);
  }
  std::size_t size() const { return inline_count_ + more_.size(); }
  std::uint32_t operator[](std::size_t k) const { return k < inline_count_ ? inline_[k] : more_[k - inline_count_]; }

 private:
  std::array<std::uint32_t, 4> inline_{};
  std::size_t inline_count_ = 0;
  std::vector<std::uint32_t> more_;
};

// How much of the reference to compute.
enum class PixelContent {
  Full,          // the near-cap count and the stencil count (the default)
  ShadowStatus,  // what a ray tracer computes: the surface seen and whether
                 // it is in shadow.  No near-cap count (cap all 0,
                 // cap_pixels_by_object empty); stencil 1 for a shadowed
                 // pixel, 0 for a lit one: the crossing search stops at the
                 // first occluder triangle found, trying first the one that
                 // shadowed the previous pixel.  Exact like Full.
};

// What the reference knows about one pixel.
struct PixelSample {
  std::uint32_t cap = 0;
  // The objects whose front faces [l, p] crosses (each once): the occluders
  // whose own near-cap covers p.
  SmallObjectSet cap_objects;
  std::optional<std::uint32_t> stencil;  // nothing when no surface is seen
  std::int32_t object = -1;              // the visible object, -1 for none
  FaceIndex face = 0;                    // its visible triangle
};

// Per-pixel results of one (scene, light) pair, row-major with row 0 the
// BOTTOM row (GL window coordinates): index = j * width + i.
struct PixelReference {
  static constexpr std::uint32_t kNothingSeen = std::numeric_limits<std::uint32_t>::max();

  PixelContent content = PixelContent::Full;
  std::size_t light = 0;
  int width = 0, height = 0;
  std::vector<std::uint32_t> cap;
  std::vector<std::uint32_t> stencil;  // kNothingSeen where no surface is seen
  std::vector<std::int32_t> object;    // -1 where no surface is seen
  std::vector<FaceIndex> face;
  // Per object: the pixels whose near-cap count it contributes to.  Z-pass
  // is right for an occluder exactly when its count is 0 (its shadow volume
  // meets no pixel centre of the near rectangle).
  std::vector<std::size_t> cap_pixels_by_object;
  FilterStats stats;
  // Building the tracer (light side, eye side: PixelReferenceTracer) and
  // tracing the pixels, wall-clock milliseconds.
  double setup_ms = 0, trace_ms = 0;

  std::size_t index(int i, int j) const { return static_cast<std::size_t>(j) * width + i; }
  bool seen(int i, int j) const { return stencil[index(i, j)] != kNothingSeen; }
  bool shadowed(int i, int j) const { return seen(i, j) && stencil[index(i, j)] > 0; }
};

// Traces single pixels; built once per (scene, light).  Thread-safe: trace()
// is const and each caller passes its own FilterStats.
//
// Building it is the reference's setup: the light side (facing, lit
// triangles, their grid around the light: light_setup.hpp) and the eye side
// (the grid around the eye: eye_setup.hpp), side by side on all cores; the
// per-triangle data of both sides is computed when a trace first reads it.
// With a LightSetupCache the light side is taken from it when the objects and
// the light have not moved since it was built: a camera path with a fixed
// scene builds it once.  With an EyeSetupCache the eye side is taken from it
// when the camera and the objects have not moved: the lights of one frame,
// or frames where only the light moves, build it once.  The traces are the
// same either way.
class PixelReferenceTracer {
 public:
  PixelReferenceTracer(const CameraSpaceScene& scene, std::size_t light, LightSetupCache* cache = nullptr,
                       EyeSetupCache* eye_cache = nullptr);
  ~PixelReferenceTracer();
  PixelReferenceTracer(const PixelReferenceTracer&) = delete;
  PixelReferenceTracer& operator=(const PixelReferenceTracer&) = delete;

  PixelSample trace(int i, int j, FilterStats* stats) const;
  // Any window point (a sub-pixel sample), same rules.
  PixelSample trace_at(const WindowPoint& p, FilterStats* stats) const;

  // The exact shadow status (true: in shadow) when it is PROVEN the same at
  // every point of the square of half-width (half_width / 2^centre.shift)
  // pixels centred on the window point `centre`, with a surface seen at every
  // point; nothing when it is not proven (crack_distance.hpp says how).
  // `last_shadower`, when given, holds a light triangle that proved an
  // earlier square in shadow (kNoShadower: none yet; a caller keeps one per
  // thread): it is tried first, and updated.  The answer is the same with or
  // without it; the hint only spares the search (neighbouring squares are
  // mostly shadowed by the same triangle).
  // `centre_hit`, when given, keeps the triangle seen at `centre` (found by
  // the first proof around that centre) for the next proof around the same
  // centre: a pixel's squares share its centre.  A fresh CentreHit knows
  // nothing; the answer is the same with or without it.
  // `status_inside`, when given, is the exact status at a point inside the
  // square (a pixel centre's, from the full-frame reference): a proof of the
  // other status cannot succeed there, so its search is skipped; the answer
  // is the same with or without it.
  static constexpr std::uint32_t kNoShadower = 0xffffffffu;
  struct CentreHit {
    bool known = false;  // the primary ray through the centre traced
    bool found = false;  // and a triangle seen there
    std::uint32_t eye_index = 0;
    Sign sigma = Sign::Zero;
    double t_value = 0, t_error = 0;  // the hit parameter's estimate and bound
  };
  std::optional<bool> proven_status_over_square(const WindowPoint& centre, std::int64_t half_width, FilterStats* stats,
                                                std::uint32_t* last_shadower = nullptr, CentreHit* centre_hit = nullptr,
                                                std::optional<bool> status_inside = std::nullopt) const;

  // The same quantities without any acceleration: every triangle is tested
  // (also those the grid around the eye leaves out, eye_setup.hpp).
  // The oracle the grids are tested against (slow).
  PixelSample trace_brute_force(int i, int j, FilterStats* stats) const;

  const CentralGrid& eye_grid() const;    // camera space, around the eye
  const CentralGrid& light_grid() const;  // WORLD space, around the light
  double setup_ms() const;                // building this tracer
  std::size_t front_facing_triangles() const;
  const CameraSpaceScene& scene() const;
  std::size_t light() const;

  struct Impl;  // src/exact/pixel_tracer_impl.hpp
  const Impl& impl() const { return *impl_; }

 private:
  std::unique_ptr<Impl> impl_;
};

// Every pixel of the camera's viewport, on all cores (TBB).
PixelReference compute_pixel_reference(const CameraSpaceScene& scene, std::size_t light,
                                       PixelContent content = PixelContent::Full);
// The same with a tracer the caller keeps (for the crack distance); setup_ms
// is the tracer's.
PixelReference compute_pixel_reference(const PixelReferenceTracer& tracer, PixelContent content = PixelContent::Full);

}  // namespace nearcap
