// Screen coverage estimates (see screen_coverage.hpp).
#include "nearcap/analysis/screen_coverage.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

namespace nearcap::analysis {
namespace {

CameraPoint lerp(const CameraPoint& a, const CameraPoint& b, double t) {
  return {a.x + t * (b.x - a.x), a.y + t * (b.y - a.y), a.z + t * (b.z - a.z), a.w + t * (b.w - a.w)};
}

constexpr int kPlanes = 5;
constexpr std::uint8_t kNearBit = 1, kAllPlanes = 0x1F;

}  // namespace

ScreenCoverage::ScreenCoverage(const Camera& camera, Depth depth)
    : f_(camera.frustum),
      near_sign_(depth == Depth::BeyondNear ? 1.0 : -1.0),
      width_(static_cast<double>(camera.width)),
      height_(static_cast<double>(camera.height)),
      x_scale_(width_ / (f_.right - f_.left)),
      y_scale_(height_ / (f_.top - f_.bottom)) {}

// Each plane's inside is >= 0 (x n / -z >= left, and so on; near: -z >= near w).
double ScreenCoverage::plane(const CameraPoint& p, int k) const {
  switch (k) {
    case 0:
      return near_sign_ * (-p.z - f_.near * p.w);
    case 1:
      return p.x * f_.near + f_.left * p.z;
    case 2:
      return -f_.right * p.z - p.x * f_.near;
    case 3:
      return p.y * f_.near + f_.bottom * p.z;
    default:
      return -f_.top * p.z - p.y * f_.near;
  }
}

// The viewport position, in pixels, of a point in front of the eye.
void ScreenCoverage::project(const CameraPoint& p, double& x, double& y) const {
  x = (p.x * f_.near / -p.z - f_.left) * x_scale_;
  y = (p.y * f_.near / -p.z - f_.bottom) * y_scale_;
}

ScreenVertex ScreenCoverage::vertex(const CameraPoint& p) const {
  // plane(p, k) for each k, as plane() evaluates it, written out: the
  // outcode is on the decision's hot path, and plane()'s switch on k is not.
  const double xn = p.x * f_.near, yn = p.y * f_.near;
  const std::array<double, kPlanes> d{near_sign_ * (-p.z - f_.near * p.w), xn + f_.left * p.z, -f_.right * p.z - xn,
                                      yn + f_.bottom * p.z, -f_.top * p.z - yn};
  ScreenVertex v;
  v.p = p;
  for (int k = 0; k < kPlanes; ++k)
    if (!(d[k] >= 0)) v.outside |= static_cast<std::uint8_t>(1u << k);
  return v;
}

double ScreenCoverage::pixels(const ScreenVertex* polygon, int n, bool near_clipped) const {
  const std::uint8_t mask = near_clipped ? kAllPlanes : static_cast<std::uint8_t>(kAllPlanes & ~kNearBit);
  std::uint8_t any = 0, all = mask;
  for (int i = 0; i < n; ++i) {
    any |= polygon[i].outside & mask;
    all &= polygon[i].outside;
  }
  if (all & mask) return 0;  // wholly outside one plane
  double twice = 0;
  if (!any) {
    // Inside the side planes (so -z >= 0) and, where clipped, the near
    // plane: the image's area as it is.
    std::array<double, 4> x, y;
    bool finite = true;
    for (int i = 0; i < n; ++i) {
      project(polygon[i].p, x[i], y[i]);
      finite = finite && -polygon[i].p.z > 0;
    }
    if (finite) {
      for (int i = 2; i < n; ++i) twice += (x[i - 1] - x[0]) * (y[i] - y[0]) - (x[i] - x[0]) * (y[i - 1] - y[0]);
      return 0.5 * std::fabs(twice);
    }
  }
  // Sutherland-Hodgman in homogeneous coordinates, on the planes it
  // crosses: each adds at most one vertex (4 + 5 at most).
  std::array<CameraPoint, 16> buffer_a, buffer_b;
  CameraPoint *a = buffer_a.data(), *b = buffer_b.data();
  int m = n;
  for (int i = 0; i < n; ++i) a[i] = polygon[i].p;
  for (int k = 0; k < kPlanes; ++k) {
    if (!(any & (1u << k))) continue;
    int q = 0;
    double dp = plane(a[0], k);
    for (int i = 0; i < m; ++i) {
      const CameraPoint &p = a[i], &s = a[i + 1 < m ? i + 1 : 0];
      const double ds = plane(s, k);
      if (dp >= 0) b[q++] = p;
      if ((dp >= 0) != (ds >= 0)) b[q++] = lerp(p, s, dp / (dp - ds));
      dp = ds;
    }
    m = q;
    std::swap(a, b);
    if (m < 3) return 0;
  }
  double x0 = 0, y0 = 0, xp = 0, yp = 0;
  for (int i = 0; i < m; ++i) {
    if (!(-a[i].z > 0)) return 0;  // the eye itself: a degenerate image
    double x, y;
    project(a[i], x, y);
    if (i == 0) {
      x0 = x;
      y0 = y;
    } else if (i >= 2) {
      twice += (xp - x0) * (y - y0) - (x - x0) * (yp - y0);
    }
    xp = x;
    yp = y;
  }
  const double area = 0.5 * std::fabs(twice);
  return std::isfinite(area) ? std::min(area, width_ * height_) : 0.0;
}

double ScreenCoverage::in_view_pieces(const ScreenVertex* polygon, int n, bool finite_far) const {
  constexpr std::uint8_t kSides = kAllPlanes & ~kNearBit;
  double pieces = 0;
  for (int i = 1; i + 1 < n; ++i) {
    const std::array<const ScreenVertex*, 3> t{&polygon[0], &polygon[i], &polygon[i + 1]};
    const std::uint8_t all = t[0]->outside & t[1]->outside & t[2]->outside;
    const std::uint8_t any = t[0]->outside | t[1]->outside | t[2]->outside;
    if (all) continue;  // beyond one plane: clipped away, or its image beside the viewport
    // Clipped at the near plane: a triangle, or a quad.
    std::array<CameraPoint, 4> clipped;
    int m = 0;
    for (int k = 0; k < 3; ++k) {
      const ScreenVertex &p = *t[k], &s = *t[(k + 1) % 3];
      const bool p_in = !(p.outside & kNearBit), s_in = !(s.outside & kNearBit);
      if (p_in) clipped[m++] = p.p;
      if (p_in != s_in) {
        const double dp = plane(p.p, 0), ds = plane(s.p, 0);
        clipped[m++] = lerp(p.p, s.p, dp / (dp - ds));
      }
    }
    // Then at a finite far plane, which every vertex at infinity (w = 0)
    // lies beyond: a polygon of m vertices, k of them at infinity, becomes
    // one of m - k + 2 (none where all are).
    int at_infinity = 0;
    for (int k = 0; finite_far && k < m; ++k) at_infinity += clipped[k].w == 0 ? 1 : 0;
    if (at_infinity == m) continue;
    const int here = at_infinity == 0 ? m - 2 : m - at_infinity;
    if (!(any & kSides)) {
      pieces += here;  // within the side planes: its image inside the viewport
      continue;
    }
    // Its image's bounds, the vertices at infinity at their vanishing points.
    double x_lo = INFINITY, x_hi = -INFINITY, y_lo = INFINITY, y_hi = -INFINITY;
    bool through_the_eye = false;  // a vertex in the eye's plane: no bounded image
    for (int k = 0; k < m && !through_the_eye; ++k) {
      through_the_eye = !(-clipped[k].z > 0);
      if (through_the_eye) break;
      double x, y;
      project(clipped[k], x, y);
      x_lo = std::min(x_lo, x);
      x_hi = std::max(x_hi, x);
      y_lo = std::min(y_lo, y);
      y_hi = std::max(y_hi, y);
    }
    if (!through_the_eye && x_hi >= 0 && x_lo <= width_ && y_hi >= 0 && y_lo <= height_) pieces += here;
  }
  return pieces;
}

namespace {

// The camera of a light's view: the near rectangle spans the frustum's left..right, bottom..top on the
// near plane, at |light.z + near| from the light.
Camera light_camera(const Camera& camera, const Vec3d& light) {
  Camera c = camera;
  const Frustum& f = camera.frustum;
  c.frustum = {f.left - light.x, f.right - light.x,           f.bottom - light.y,
               f.top - light.y,  std::fabs(light.z + f.near), f.far};
  return c;
}

}  // namespace

LightView::LightView(const Camera& camera, const Vec3d& light)
    : light_(light),
      beyond_(light.z + camera.frustum.near < 0),
      coverage_(light_camera(camera, light), ScreenCoverage::Depth::BeforeNear) {}

ScreenVertex LightView::vertex(const Vec3d& p) const {
  return coverage_.vertex({p.x - light_.x, p.y - light_.y, beyond_ ? light_.z - p.z : p.z - light_.z, 1});
}

}  // namespace nearcap::analysis
