// The look-at camera (see scene.hpp): view and frustum computed once in
// double, as gluLookAt and gluPerspective would; those doubles are then the
// scene (docs/scene-format.md, "Exactness convention").
#include <algorithm>
#include <cmath>

#include "nearcap/scene/scene.hpp"

namespace nearcap {

Camera look_at_camera(const Vec3d& eye, const Vec3d& target, const Vec3d& up, double fovy_deg, double near, double far,
                      int width, int height) {
  // gluLookAt's normalisation; when the squared length would underflow or
  // overflow (a 1e-300 view direction or up vector, a 1e200 offset), the
  // vector is first scaled by its largest component.  Every vector whose
  // squared length is a normal double keeps gluLookAt's exact arithmetic.
  // A zero vector gives NaN, which the scene reader reports.
  auto normalize = [](const Vec3d& v) {
    const double n2 = dot(v, v);
    if (std::isnormal(n2) && std::isfinite(n2)) {
      const double n = std::sqrt(n2);
      return Vec3d{v.x / n, v.y / n, v.z / n};
    }
    const double m = std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
    const Vec3d w{v.x / m, v.y / m, v.z / m};
    const double n = std::sqrt(dot(w, w));
    return Vec3d{w.x / n, w.y / n, w.z / n};
  };
  const Vec3d f = normalize(target - eye);
  const Vec3d s = normalize(cross(f, up));
  const Vec3d u = cross(s, f);
  Camera c;
  c.view.rows = {{{s.x, s.y, s.z, -dot(s, eye)}, {u.x, u.y, u.z, -dot(u, eye)}, {-f.x, -f.y, -f.z, dot(f, eye)}}};
  const double top = near * std::tan(fovy_deg * (M_PI / 360.0));
  const double right = top * (static_cast<double>(width) / static_cast<double>(height));
  c.frustum = Frustum{-right, right, -top, top, near, far};
  c.width = width;
  c.height = height;
  return c;
}

}  // namespace nearcap
