// nearcap/view/fly_camera.hpp — the viewer's fly camera: a scene camera's view
// moved in steps along its own axes and turned about its up and right axes.
//
// It starts from the scene's view matrix and gives it back unchanged until
// the first move or turn (so the viewer's first frame is the scene file's
// frame bit for bit); after that the view is rebuilt from an orthonormal
// basis and the eye, in double.  Turning left/right is about the starting
// view's up axis (the horizon stays level), up/down about the current right
// axis.  The frustum is not the fly camera's: the scene's stays as it is.
#pragma once

#include "nearcap/numeric/vec3.hpp"

namespace nearcap::view {

class FlyCamera {
 public:
  // `view`: world -> camera space, with an invertible linear part; `step`:
  // the distance one move covers (world units, > 0).
  FlyCamera(const Affine3d& view, double step);

  // Moves the eye by the given numbers of steps along the camera's forward
  // (-z), right (+x) and up (+y) axes.
  void move(double forward, double right, double up);
  // Turns by the given angles: yaw positive to the left, pitch positive up.
  void turn(double yaw_degrees, double pitch_degrees);
  void scale_step(double factor) { step_ *= factor; }

  Affine3d view() const;
  const Vec3d& eye() const { return eye_; }
  Vec3d forward() const { return -1.0 * back_; }
  double step() const { return step_; }

 private:
  Affine3d initial_;
  bool changed_ = false;
  Vec3d eye_, right_, up_, back_;  // world space; right, up, back orthonormal
  Vec3d yaw_axis_;
  double step_;
};

}  // namespace nearcap::view
