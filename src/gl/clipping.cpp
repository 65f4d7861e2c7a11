// Homogeneous clipping (see clipping.hpp).
#include "nearcap/gl/clipping.hpp"

#include <array>
#include <cmath>

#include <algorithm>
#include <utility>
#include <vector>

namespace nearcap::gl {
namespace {

enum class Plane { Near, WMin, Far, Left, Right, Bottom, Top };

float distance(const Vec4f& v, Plane p, float g, float w_min, DepthMapping m) {
  switch (p) {
    case Plane::Near:
      return near_plane_distance(v, m);
    case Plane::WMin:
      return v.w - w_min;
    case Plane::Far:
      return far_plane_distance(v, m);
    case Plane::Left:
      return v.x + g * v.w;
    case Plane::Right:
      return g * v.w - v.x;
    case Plane::Bottom:
      return v.y + g * v.w;
    case Plane::Top:
      return g * v.w - v.y;
  }
  return 0;
}

// distance() of a triangle's three vertices to one plane.
std::array<float, 3> distances(const Vec4f& a, const Vec4f& b, const Vec4f& c, Plane p, float g, float w_min,
                               DepthMapping m) {
  return {distance(a, p, g, w_min, m), distance(b, p, g, w_min, m), distance(c, p, g, w_min, m)};
}

Vec4f interpolate(const Vec4f& in, const Vec4f& out, float t) {
  return {in.x + t * (out.x - in.x), in.y + t * (out.y - in.y), in.z + t * (out.z - in.z), in.w + t * (out.w - in.w)};
}

// A vertex with the distance the clipper carries for a gl_ClipDistance plane
// (ClipSettings::depth_plane_as_clip_distance; unused otherwise).
struct ClipVertex {
  Vec4f p;
  float clip_distance = 0;
};

ClipVertex interpolate(const ClipVertex& in, const ClipVertex& out, float t) {
  return {interpolate(in.p, out.p, t), in.clip_distance + t * (out.clip_distance - in.clip_distance)};
}

// The largest |coordinate| of a clip-space vertex, and the factor by which an
// inside vertex must exceed the outside one's for the cut to start from the
// outside vertex (bundled scenes: at most ~50).
inline float magnitude(const Vec4f& v) {
  return std::max(std::max(std::fabs(v.x), std::fabs(v.y)), std::max(std::fabs(v.z), std::fabs(v.w)));
}
constexpr float kCancellation = 1024.0f;

// The plane w >= w_min under near depth clamp.  Mesa has no such plane: its
// x and y planes leave w >= 0, and a side that passes the eye closer than
// about 10^-5 of the near distance covers a wedge of the frame that llvmpipe
// draws and the spec clipper's plane cuts.  The Mesa model keeps the plane,
// 2^-24 of the spec clipper's (near x 1e-5 x 2^-24, about near x 2^-40),
// only to keep w = 0 out of the divide; cutting from the endpoint nearer the
// plane, it lands there accurately.  The spec clipper, cutting from the
// inside vertex, needs its plane above that cut's rounding.
inline float w_min_of(const ClipSettings& settings) {
  return settings.mesa ? settings.w_min * 0x1p-24f : settings.w_min;
}

// One Sutherland-Hodgman stage.  `on_plane`, when given, receives for each
// output vertex whether it lies in plane p (made here, or at distance 0).
// `carried`: plane p's distance is the vertex's clip_distance.
// The stage's polygon goes to `out` (cleared first; not `poly`).
void clip_against(const std::vector<ClipVertex>& poly, Plane p, float g, float w_min, DepthMapping m,
                  std::vector<ClipVertex>& out, std::vector<bool>* on_plane = nullptr, bool mesa = false,
                  bool carried = false) {
  out.clear();
  const std::size_t n = poly.size();
  for (std::size_t k = 0; k < n; ++k) {
    const ClipVertex& a = poly[k];
    const ClipVertex& b = poly[(k + 1) % n];
    const float da = carried ? a.clip_distance : distance(a.p, p, g, w_min, m);
    const float db = carried ? b.clip_distance : distance(b.p, p, g, w_min, m);
    const bool a_in = da >= 0, b_in = db >= 0;
    if (a_in) {
      out.push_back(a);
      if (on_plane) on_plane->push_back(da == 0);
    }
    if (mesa) {
      // draw_pipe_clip.c (22.3): a new vertex wherever DIFFERENT_SIGNS (a
      // product <= 0 and the distances differ: a vertex exactly on the plane
      // next to one inside makes a near-duplicate too).
      if (da * db <= 0.0f && da - db != 0.0f) {
        // From the endpoint nearer the plane (on a tie, the inside one).
        if (db < 0)  // going out
          out.push_back(-db < da ? interpolate(b, a, db / (db - da)) : interpolate(a, b, -da / (db - da)));
        else  // coming back in
          out.push_back(-da < db ? interpolate(a, b, da / (da - db)) : interpolate(b, a, -db / (da - db)));
        if (on_plane) on_plane->push_back(true);
      }
      continue;
    }
    if (a_in != b_in) {
      // From the inside vertex towards the outside one, unless that cancels
      // catastrophically: an inside vertex far larger than the outside one
      // (a vertex extruded to a far light) with the outside one the nearer
      // the plane.  Then from the outside one, as Mesa does.  Decided from
      // the edge alone, so a shared edge is still cut alike from both sides.
      const ClipVertex& in = a_in ? a : b;
      const ClipVertex& o = a_in ? b : a;
      const float d_in = a_in ? da : db, d_out = a_in ? db : da;
      if (-d_out < d_in && magnitude(in.p) > kCancellation * magnitude(o.p))
        out.push_back(interpolate(o, in, d_out / (d_out - d_in)));
      else
        out.push_back(interpolate(in, o, d_in / (d_in - d_out)));
      if (on_plane) on_plane->push_back(true);
    }
  }
}

}  // namespace

std::vector<Vec4f> clip_triangle(const Vec4f& a, const Vec4f& b, const Vec4f& c, const ClipSettings& settings) {
  std::vector<Vec4f> polygon;
  clip_triangle(a, b, c, settings, polygon);
  return polygon;
}

void clip_triangle(const Vec4f& a, const Vec4f& b, const Vec4f& c, const ClipSettings& settings,
                   std::vector<Vec4f>& polygon) {
  TriangleClipper(settings).clip(a, b, c, polygon);
}

TriangleClipper::TriangleClipper(const ClipSettings& settings) : settings_(settings) {
  settings_.w_min = w_min_of(settings);  // once per draw
  std::array<Plane, 6> planes{};
  std::size_t count = 0;
  // Mesa with one depth side clamped through GL_DEPTH_CLAMP and a
  // gl_ClipDistance plane: the x and y planes, then that plane (`carried`).
  carried_ = settings.mesa && settings.depth_plane_as_clip_distance;
  if (carried_) {
    for (Plane p : {Plane::Right, Plane::Left, Plane::Top, Plane::Bottom}) planes[count++] = p;
    planes[count++] = settings.clip_near ? Plane::Near : Plane::Far;
  } else {
    if (settings.far_first && settings.clip_far) planes[count++] = Plane::Far;
    if (!settings.skip_near_side) planes[count++] = settings.clip_near ? Plane::Near : Plane::WMin;
    if (settings.clip_far && !settings.far_first) planes[count++] = Plane::Far;
    for (Plane p : {Plane::Left, Plane::Right, Plane::Bottom, Plane::Top}) planes[count++] = p;
  }
  if (settings.mesa && !carried_) {
    // Mesa's plane order (draw_context.c): right, left, top, bottom, near, far.
    std::array<Plane, 6> ordered{};
    std::size_t n = 0;
    for (Plane p : {Plane::Right, Plane::Left, Plane::Top, Plane::Bottom, Plane::Near, Plane::WMin, Plane::Far})
      for (std::size_t k = 0; k < count; ++k)
        if (planes[k] == p) ordered[n++] = p;
    planes = ordered;
  }
  for (std::size_t k = 0; k < count; ++k) planes_[k] = static_cast<std::uint8_t>(planes[k]);
  count_ = count;
}

void TriangleClipper::clip(const Vec4f& a, const Vec4f& b, const Vec4f& c, std::vector<Vec4f>& polygon) const {
  polygon.clear();
  const ClipSettings& settings = settings_;
  const float g = settings.guard_band, w_min = settings.w_min;
  const DepthMapping m = settings.depth_mapping;
  // Trivial accept: no plane separates any vertex (the common case); trivial
  // reject: one plane has all three outside (clipping would leave nothing).
  // At the input vertices a carried distance is the plane's own.
  bool all_inside = true;
  for (std::size_t k = 0; k < count_; ++k) {
    const std::array<float, 3> d = distances(a, b, c, static_cast<Plane>(planes_[k]), g, w_min, m);
    if (d[0] < 0 && d[1] < 0 && d[2] < 0) return;
    all_inside = all_inside && d[0] >= 0 && d[1] >= 0 && d[2] >= 0;
  }
  if (all_inside) {
    polygon.insert(polygon.end(), {a, b, c});
    return;
  }
  clip_at_planes(a, b, c, polygon);
}

TriangleClipper::VertexCode TriangleClipper::code(const Vec4f& v) const {
  VertexCode out;
  for (std::size_t k = 0; k < count_; ++k) {
    const float d =
        distance(v, static_cast<Plane>(planes_[k]), settings_.guard_band, settings_.w_min, settings_.depth_mapping);
    if (d < 0) out.outside = static_cast<std::uint8_t>(out.outside | (1u << k));
    out.inside = out.inside && d >= 0;
  }
  return out;
}

void TriangleClipper::clip(const Vec4f& a, const Vec4f& b, const Vec4f& c, VertexCode code_a, VertexCode code_b,
                           VertexCode code_c, std::vector<Vec4f>& polygon) const {
  polygon.clear();
  if ((code_a.outside & code_b.outside & code_c.outside) != 0) return;  // one plane has all three outside
  if (code_a.inside && code_b.inside && code_c.inside) {
    polygon.insert(polygon.end(), {a, b, c});
    return;
  }
  clip_at_planes(a, b, c, polygon);
}

void TriangleClipper::clip_at_planes(const Vec4f& a, const Vec4f& b, const Vec4f& c,
                                     std::vector<Vec4f>& polygon) const {
  const ClipSettings& settings = settings_;
  const float g = settings.guard_band, w_min = settings.w_min;
  const DepthMapping m = settings.depth_mapping;
  // The stages' polygons, kept per thread with their capacity: a draw clips
  // many triangles, and none allocates.
  thread_local std::vector<ClipVertex> poly, next;
  poly.assign({{a}, {b}, {c}});
  if (carried_) {
    const Plane p = static_cast<Plane>(planes_[count_ - 1]);
    for (ClipVertex& v : poly) v.clip_distance = distance(v.p, p, 0.0f, 0.0f, m);
  }
  for (std::size_t k = 0; k < count_; ++k) {
    const Plane p = static_cast<Plane>(planes_[k]);
    if (settings.mesa) {
      // Mesa clips only at the planes some input vertex is outside (its clipmask).
      const std::array<float, 3> d = distances(a, b, c, p, g, w_min, m);
      if (!(d[0] < 0 || d[1] < 0 || d[2] < 0)) continue;
    }
    clip_against(poly, p, g, w_min, m, next, nullptr, settings.mesa, carried_ && k + 1 == count_);
    std::swap(poly, next);
    if (poly.size() < 3) return;
  }
  for (const ClipVertex& v : poly) polygon.push_back(v.p);
}

namespace {

// The first clipping stage alone, against plane p, with the flags of the
// vertices that lie in it.
NearClippedPolygon clip_first_stage(const Vec4f& a, const Vec4f& b, const Vec4f& c, Plane p, DepthMapping mapping) {
  NearClippedPolygon out;
  std::vector<ClipVertex> poly;
  clip_against({{a}, {b}, {c}}, p, 0.0f, 0.0f, mapping, poly, &out.on_near_plane);
  if (poly.size() < 3) {
    out.on_near_plane.clear();
    return out;
  }
  out.vertices.reserve(poly.size());
  for (const ClipVertex& v : poly) out.vertices.push_back(v.p);
  return out;
}

}  // namespace

NearClippedPolygon clip_to_near_plane(const Vec4f& a, const Vec4f& b, const Vec4f& c, DepthMapping mapping) {
  return clip_first_stage(a, b, c, Plane::Near, mapping);
}

NearClippedPolygon clip_to_far_plane(const Vec4f& a, const Vec4f& b, const Vec4f& c, DepthMapping mapping) {
  return clip_first_stage(a, b, c, Plane::Far, mapping);
}

}  // namespace nearcap::gl
