// The viewer's fly camera (see fly_camera.hpp).
#include "nearcap/view/fly_camera.hpp"

#include <cmath>

#include "nearcap/error.hpp"

namespace nearcap::view {
namespace {

Vec3d normalized(const Vec3d& v) {
  const double n = std::sqrt(dot(v, v));
  return (1.0 / n) * v;
}

// v turned by `radians` about the unit axis k (right-handed).
Vec3d rotated(const Vec3d& v, const Vec3d& k, double radians) {
  const double c = std::cos(radians), s = std::sin(radians);
  return c * v + s * cross(k, v) + (dot(k, v) * (1 - c)) * k;
}

}  // namespace

FlyCamera::FlyCamera(const Affine3d& view, double step) : initial_(view), step_(step) {
  if (!(step > 0) || !std::isfinite(step))
    throw Error(ErrorKind::Usage, "the fly camera's step must be a positive finite distance");
  // Rows of the linear part: the camera's x, y, z axes in world space (scaled
  // when the view scales); the eye is L^-1 (-t).
  const auto& r = initial_.rows;
  const Vec3d x{r[0][0], r[0][1], r[0][2]}, y{r[1][0], r[1][1], r[1][2]}, z{r[2][0], r[2][1], r[2][2]};
  const double det = dot(x, cross(y, z));
  if (!(std::fabs(det) > 0) || !std::isfinite(det))
    throw Error(ErrorKind::Camera, "the view matrix is not invertible: no eye to fly");
  // L^-1 = adj(L) / det: its columns are (y x z, z x x, x x y) / det.
  const Vec3d t{-r[0][3], -r[1][3], -r[2][3]};
  eye_ = (t.x / det) * cross(y, z) + (t.y / det) * cross(z, x) + (t.z / det) * cross(x, y);
  back_ = normalized(z);
  right_ = normalized(cross(y, back_));
  up_ = cross(back_, right_);
  yaw_axis_ = up_;
}

void FlyCamera::move(double forward, double right, double up) {
  eye_ = eye_ + (step_ * (up)) * up_ + (step_ * right) * right_ + (-step_ * forward) * back_;
  changed_ = true;
}

void FlyCamera::turn(double yaw_degrees, double pitch_degrees) {
  const double yaw = yaw_degrees * (M_PI / 180.0), pitch = pitch_degrees * (M_PI / 180.0);
  right_ = rotated(right_, yaw_axis_, yaw);
  up_ = rotated(up_, yaw_axis_, yaw);
  back_ = rotated(back_, yaw_axis_, yaw);
  up_ = rotated(up_, right_, pitch);
  back_ = rotated(back_, right_, pitch);
  // Rounding drift removed: back kept, right and up rebuilt from it.
  back_ = normalized(back_);
  right_ = normalized(cross(up_, back_));
  up_ = cross(back_, right_);
  changed_ = true;
}

Affine3d FlyCamera::view() const {
  if (!changed_) return initial_;
  Affine3d v;
  const Vec3d* axes[3] = {&right_, &up_, &back_};
  for (int k = 0; k < 3; ++k) v.rows[k] = {axes[k]->x, axes[k]->y, axes[k]->z, -dot(*axes[k], eye_)};
  return v;
}

}  // namespace nearcap::view
