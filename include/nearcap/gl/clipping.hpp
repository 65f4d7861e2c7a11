// nearcap/gl/clipping.hpp — homogeneous clipping of a triangle as GL specifies
// it, in float32.
//
// Planes, as distances d(v) >= 0 inside: near z + w, far w - z (left out with
// an infinite far plane, where w - z is exactly 0 at infinity, or with depth
// clamp), and a guard band |x|, |y| <= g w; with the reversed depth mapping
// (float_transforms.hpp: GL_ZERO_TO_ONE) near w - z and far z
// (g = 1 clips to the view volume; hardware uses a wide band so that x and y
// are rarely clipped).  Sutherland-Hodgman, one plane after the other; an
// intersection is interpolated from the INSIDE vertex towards the outside one
// with t = d_in / (d_in - d_out), so an edge shared by two triangles is cut
// at the same point from both sides; except where that cancels away every
// digit: an inside vertex over 1024 times the outside one's largest
// coordinate (a side extruded towards a far light) with the outside one the
// nearer the plane, cut from the outside one (the choice depends on the edge
// alone, so shared edges still agree).  Mesa's clipper interpolates from the
// endpoint nearer the plane, in its own plane order: ClipSettings::mesa.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "nearcap/gl/float_transforms.hpp"

namespace nearcap::gl {

// The camera's near and far planes as distances (>= 0 inside), and the z of
// the near plane's points, for a depth mapping: each one float operation,
// the one the clipper does.
inline float near_plane_distance(const Vec4f& v, DepthMapping m) {
  return m == DepthMapping::Standard ? v.z + v.w : v.w - v.z;
}
inline float far_plane_distance(const Vec4f& v, DepthMapping m) {
  return m == DepthMapping::Standard ? v.w - v.z : v.z;
}
inline float near_plane_z(float w, DepthMapping m) { return m == DepthMapping::Standard ? -w : w; }

struct ClipSettings {
  bool clip_far = true;     // false: depth clamp
  float guard_band = 8192;  // in NDC units; x and y clipped at |x| <= guard_band * w
  // false: depth clamp (GL_DEPTH_CLAMP disables near and far clipping).  The
  // divide still needs w > 0, so the plane w >= w_min takes the near plane's
  // place; fragments in front of the near plane get depth 0 after clamping.
  // With mesa, the plane is 2^-24 of this (Mesa has none: clipping.cpp,
  // w_min_of); with depth_plane_as_clip_distance, none.
  bool clip_near = true;
  float w_min = 1e-6f;
  // No near-side plane at all (neither near nor w_min): for primitives whose
  // vertices the near plane's clipping made (the clipped-sides near cap,
  // gl/near_plane_cap.hpp), which must be cut by the remaining planes exactly
  // where the polygons they close were cut, and not again at the near plane
  // they lie on only to within rounding.  Overrides clip_near.
  bool skip_near_side = false;
  // The far plane first, then the near plane (ZF+'s volumes and far cap,
  // near_plane_cap.hpp: their far edges then come from the input vertices,
  // as the near cap's near edges do).
  bool far_first = false;
  DepthMapping depth_mapping = DepthMapping::Standard;  // which planes are near and far
  // Mesa's clipper (draw_pipe_clip.c, draw_context.c) instead: only the
  // planes some input vertex is outside, in its order (right, left, top,
  // bottom, near, far); a new vertex wherever the distances d_prev, d of an
  // edge have d_prev d <= 0 and differ (so also next to a vertex exactly on
  // the plane), interpolated from the endpoint NEARER the plane (on a tie
  // the inside one), c + t (o - c) with t = d_c / (d_c - d_o).  An edge
  // shared by two triangles is still cut at the same point from both sides.
  bool mesa = false;
  // With mesa: one depth clamp side done as the renderer does it on a driver
  // without GL_AMD_depth_clamp_separate (render/draw_state.hpp):
  // GL_DEPTH_CLAMP, and the plane that still clips (near when only the far
  // side clamps, far when only the near side does) as gl_ClipDistance[0]
  // written by the vertex program with the same one float operation.  Mesa
  // clips a user plane after the view volume's, and reads its distance from
  // the vertex, so at a vertex the x and y planes made it is the distance
  // interpolated like the position (c + t (o - c)), not the distance of the
  // interpolated position.  No w >= w_min plane: the x and y planes keep
  // w >= 0.  Without mesa this changes nothing (the spec clips the same plane).
  bool depth_plane_as_clip_distance = false;
};

// The clipped polygon (0 or 3+ vertices) of triangle (a, b, c), in order.
std::vector<Vec4f> clip_triangle(const Vec4f& a, const Vec4f& b, const Vec4f& c, const ClipSettings& settings);
// The same into `polygon` (replacing its contents; its capacity is kept, so a
// caller clipping many triangles allocates nothing for the unclipped ones).
void clip_triangle(const Vec4f& a, const Vec4f& b, const Vec4f& c, const ClipSettings& settings,
                   std::vector<Vec4f>& polygon);

// clip_triangle for the triangles of one draw: the planes and their order
// worked out once from the settings.  clip(a, b, c, polygon) is
// clip_triangle(a, b, c, settings, polygon), bit for bit.
class TriangleClipper {
 public:
  explicit TriangleClipper(const ClipSettings& settings);
  void clip(const Vec4f& a, const Vec4f& b, const Vec4f& c, std::vector<Vec4f>& polygon) const;
  // What clip()'s trivial accept and reject read of one vertex: the planes
  // it is outside (distance < 0), a bit each, and whether it is inside every
  // plane (distance >= 0 at each; not the same as no bit set where a
  // distance is NaN).  A vertex shared by many triangles (an indexed draw)
  // is coded once.
  struct VertexCode {
    std::uint8_t outside = 0;
    bool inside = true;
  };
  VertexCode code(const Vec4f& v) const;
  // clip(a, b, c, polygon) from the vertices' codes: the same polygon.
  void clip(const Vec4f& a, const Vec4f& b, const Vec4f& c, VertexCode code_a, VertexCode code_b, VertexCode code_c,
            std::vector<Vec4f>& polygon) const;

 private:
  // clip() past the trivial accept and reject: the triangle through every
  // plane.  Kept out of clip(), whose trivial tests run for every triangle.
  [[gnu::noinline]] void clip_at_planes(const Vec4f& a, const Vec4f& b, const Vec4f& c,
                                        std::vector<Vec4f>& polygon) const;
  ClipSettings settings_;                 // its w_min the plane this clipper cuts at (clipping.cpp, w_min_of)
  std::array<std::uint8_t, 6> planes_{};  // clipping.cpp's planes, in clipping order
  std::size_t count_ = 0;
  bool carried_ = false;  // the last plane's distance is a gl_ClipDistance (depth_plane_as_clip_distance)
};

// The first stage of clip_triangle with near clipping: triangle (a, b, c)
// clipped against the near plane alone, with the same arithmetic (so its
// vertices are bit for bit the ones clip_triangle passes on to the other
// planes), and for each vertex whether it lies in the near plane: made by
// the near plane's intersection, or an input vertex at distance exactly 0.
struct NearClippedPolygon {
  std::vector<Vec4f> vertices;  // empty when the whole triangle is in front of the near plane
  std::vector<bool> on_near_plane;
};
NearClippedPolygon clip_to_near_plane(const Vec4f& a, const Vec4f& b, const Vec4f& c,
                                      DepthMapping mapping = DepthMapping::Standard);

// The first stage of clip_triangle with ClipSettings::far_first: triangle
// (a, b, c) clipped against the far plane alone, with the same arithmetic;
// `on_near_plane` then says which vertices lie in the FAR plane (made by its
// intersection, or an input vertex at distance exactly 0).  For ZF+'s far cap.
NearClippedPolygon clip_to_far_plane(const Vec4f& a, const Vec4f& b, const Vec4f& c,
                                     DepthMapping mapping = DepthMapping::Standard);

}  // namespace nearcap::gl
