// nearcap/analysis/screen_coverage.hpp — the fragments a pass will
// rasterize, estimated before drawing from the triangles it will draw.
//
// A triangle covers, up to the rasterizer's sampling of pixel centres, the
// area of its image clipped to the view volume.  In homogeneous camera space
// (w = 1 a point, w = 0 a direction from the light: a shadow volume's
// vertex at infinity) it is clipped by the near plane (not for a
// depth-clamped draw) and by the frustum's four side planes, projected onto
// the viewport, and its area counted in pixels.  A pass that draws a closed
// surface with both facings and no culling rasterizes the sum of its
// triangles' areas: every pixel once per layer.
//
// A near-cap covers the near plane's section of the shadow volume, each
// pixel as many times as the volume's layers contain it there (what its
// count must start at).  A point of the near plane lies in as many layers as
// the segment from the light to it crosses light-facing faces of the
// occluder: the near-cap's pixels are those faces' coverage seen from the
// light, clipped to the part between the light and the near plane
// (Depth::BeforeNear) and to the near rectangle, the paper's near-cap pass
// drawn as a coverage sum.
//
// Estimates in double; tests/cost_decision_test.cpp compares them with the
// emulation's fragment counters.
#pragma once

#include <array>
#include <cstdint>

#include "nearcap/scene/scene.hpp"

namespace nearcap::analysis {

// A homogeneous point of camera space: w = 1 a point, 0 a direction.
struct CameraPoint {
  double x = 0, y = 0, z = 0, w = 0;
};

// A vertex ready for coverage: its point, and which planes of the view
// volume it is outside (bit 0 the near plane, bits 1-4 left, right, bottom,
// top).
struct ScreenVertex {
  CameraPoint p;
  std::uint8_t outside = 0;
};

class ScreenCoverage {
 public:
  // Which side of the near plane is drawn: beyond it (a camera's view), or
  // between the eye and it (what a light sees of an occluder in front of
  // the near plane, projected onto it).
  enum class Depth { BeyondNear, BeforeNear };
  explicit ScreenCoverage(const Camera& camera, Depth depth = Depth::BeyondNear);

  ScreenVertex vertex(const CameraPoint& p) const;
  // Pixels covered by the convex polygon (3 or 4 vertices, in order) clipped
  // to the view volume; `near_clipped` false: a depth-clamped draw, not
  // clipped by the near plane (only in front of the eye).
  double pixels(const ScreenVertex* polygon, int n, bool near_clipped = true) const;
  double triangle_pixels(const ScreenVertex& a, const ScreenVertex& b, const ScreenVertex& c) const {
    const std::array<ScreenVertex, 3> t{a, b, c};
    return pixels(t.data(), 3);
  }
  // The triangles a GL sets up for the convex polygon (3 or 4 vertices, in
  // order, drawn as the fan v0 v_i v_i+1) whose bounds meet the viewport
  // (gl::DrawCounters::in_view): each fan triangle clipped at the near
  // plane and, with `finite_far`, at a finite far plane, beyond which
  // every vertex at infinity (w = 0) lies (at an infinite far plane those
  // vertices lie on it and stay); the side planes are the rasterizer's
  // guard band, not a clip.  Its pieces count where the bounding box of
  // their image, in pixels (a vertex at infinity at its vanishing point),
  // meets the viewport's.  A triangle that covers no pixel centre can
  // count: a sliver across a corner, beside an edge within a pixel.
  double in_view_pieces(const ScreenVertex* polygon, int n, bool finite_far) const;

 private:
  double plane(const CameraPoint& p, int k) const;
  void project(const CameraPoint& p, double& x, double& y) const;
  Frustum f_;
  double near_sign_;                           // +1 beyond the near plane, -1 before it
  double width_, height_, x_scale_, y_scale_;  // pixels per unit of the near rectangle
};

// The view from a point light (camera space, not in the near plane) of the
// near rectangle, at the near plane's distance from the light: what a
// near-cap covers.  A light beyond the near plane looks back towards the eye,
// its view mirrored in depth (the same areas).
class LightView {
 public:
  LightView(const Camera& camera, const Vec3d& light);
  ScreenVertex vertex(const Vec3d& camera_point) const;
  double triangle_pixels(const ScreenVertex& a, const ScreenVertex& b, const ScreenVertex& c) const {
    return coverage_.triangle_pixels(a, b, c);
  }
  double in_view_pieces(const ScreenVertex* polygon, int n) const {
    return coverage_.in_view_pieces(polygon, n, false);
  }

 private:
  Vec3d light_;
  bool beyond_;  // the light beyond the near plane
  ScreenCoverage coverage_;
};

}  // namespace nearcap::analysis
