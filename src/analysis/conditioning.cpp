// Conditioning features of one (frame, light) (see conditioning.hpp).
#include "nearcap/analysis/conditioning.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "nearcap/numeric/singular_values.hpp"

namespace nearcap::analysis {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::array<std::array<double, 4>, 4> entries(const gl::Mat4f& m) {
  std::array<std::array<double, 4>, 4> a{};
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) a[r][c] = m.at(r, c);
  return a;
}

std::array<std::array<double, 4>, 4> product(const std::array<std::array<double, 4>, 4>& a,
                                             const std::array<std::array<double, 4>, 4>& b) {
  std::array<std::array<double, 4>, 4> p{};
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      for (int k = 0; k < 4; ++k) p[r][c] += a[r][k] * b[k][c];
  return p;
}

double float_ulp(double x) {
  const float f = std::fabs(static_cast<float>(x));
  return static_cast<double>(std::nextafter(f, std::numeric_limits<float>::infinity()) - f);
}

// The diagonal of the bounding box of the points each object vertex and each
// light `add`s.
template <class AddPoints>
double diagonal_of(AddPoints&& add_points) {
  Vec3d lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
           std::numeric_limits<double>::infinity()};
  Vec3d hi = -1.0 * lo;
  add_points([&](const Vec3d& p) {
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], p[a]);
      hi[a] = std::max(hi[a], p[a]);
    }
  });
  return std::sqrt(dot(hi - lo, hi - lo));
}

// The diagonal of the scene's bounding box (vertices in world space, lights).
double scene_diagonal(const Scene& scene) {
  return diagonal_of([&scene](auto&& add) {
    for (const SceneObject& o : scene.objects)
      for (const Vec3d& v : o.mesh->positions) add(o.object_to_world.apply(v));
    for (const Light& l : scene.lights) add(l.position);
  });
}

// No larger than scene_diagonal, without a pass over every vertex: the box
// of the lights and the first, middle and last vertex of each object, each
// computed as scene_diagonal computes it.  Its points are some of that box's,
// so each extent, each rounded operation after it and the diagonal are no
// larger.
double scene_diagonal_lower_bound(const Scene& scene) {
  return diagonal_of([&scene](auto&& add) {
    for (const SceneObject& o : scene.objects) {
      const std::vector<Vec3d>& positions = o.mesh->positions;
      if (positions.empty()) continue;
      for (const std::size_t v : {std::size_t{0}, positions.size() / 2, positions.size() - 1})
        add(o.object_to_world.apply(positions[v]));
    }
    for (const Light& l : scene.lights) add(l.position);
  });
}

// The largest eye distance -z of a vertex estimate, 0 where none is in
// front of the eye.  Four running maxima (a max is exact and ignores a NaN
// either way): the loop is not one chain of dependent comparisons.
double farthest_in_front(const CameraSpaceScene& cs) {
  std::array<double, 4> far{};
  for (std::size_t o = 0; o < cs.object_count(); ++o) {
    const std::size_t n = cs.mesh(o).positions.size();
    VertexIndex v = 0;
    for (; v + 4 <= n; v += 4)
      for (int k = 0; k < 4; ++k) far[k] = std::max(far[k], -cs.vertex_estimate(o, v + k).z);
    for (; v < n; ++v) far[0] = std::max(far[0], -cs.vertex_estimate(o, v).z);
  }
  return std::max({far[0], far[1], far[2], far[3]});
}

// depth_step_over_size's formula; rounded division by a smaller diagonal
// gives no smaller step.
double depth_step(double farthest, double near, gl::DepthFormat format, gl::DepthMapping mapping, double diagonal) {
  if (!(farthest > near) || !(diagonal > 0)) return kNaN;
  if (mapping == gl::DepthMapping::Reversed && format == gl::DepthFormat::Float32)
    return std::ldexp(farthest, -23) / diagonal;
  return std::ldexp(farthest * farthest / near, -24) / diagonal;
}

double coordinate_over_size(const Scene& scene) {
  double largest = 0;
  Vec3d lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
           std::numeric_limits<double>::infinity()};
  Vec3d hi = -1.0 * lo;
  auto add = [&](const Vec3d& p) {
    for (int a = 0; a < 3; ++a) {
      largest = std::max(largest, std::fabs(p[a]));
      lo[a] = std::min(lo[a], p[a]);
      hi[a] = std::max(hi[a], p[a]);
    }
  };
  for (const SceneObject& o : scene.objects)
    for (const Vec3d& v : o.mesh->positions) add(o.object_to_world.apply(v));
  for (const Light& l : scene.lights) add(l.position);
  const double diagonal = std::sqrt(dot(hi - lo, hi - lo));
  return diagonal > 0 ? largest / diagonal : kNaN;
}

}  // namespace

double depth_step_over_size(const CameraSpaceScene& cs) {
  return depth_step_over_size(cs, cs.scene().camera.frustum.near, gl::DepthFormat::Fixed24, gl::DepthMapping::Standard);
}

double depth_step_over_size(const CameraSpaceScene& cs, double near, gl::DepthFormat format, gl::DepthMapping mapping) {
  return depth_step(farthest_in_front(cs), near, format, mapping, scene_diagonal(cs.scene()));
}

DepthStepAgainstLimit depth_step_against_limit(const CameraSpaceScene& cs, double near, gl::DepthFormat format,
                                               gl::DepthMapping mapping) {
  const double farthest = farthest_in_front(cs);
  const double bound = depth_step(farthest, near, format, mapping, scene_diagonal_lower_bound(cs.scene()));
  if (bound < kDepthLimitedStep) return {bound, true};
  return {depth_step(farthest, near, format, mapping, scene_diagonal(cs.scene())), false};
}

ConditioningFeatures conditioning_features(const CameraSpaceScene& cs, std::size_t light,
                                           const gl::LightFrustumChoice& choice, gl::Arithmetic arithmetic) {
  return conditioning_features(cs, light, gl::light_frustum(cs.scene(), light, choice), arithmetic);
}

ConditioningFeatures conditioning_features(const CameraSpaceScene& cs, std::size_t light, const gl::LightFrustum& lf,
                                           gl::Arithmetic arithmetic) {
  const Scene& scene = cs.scene();
  const Frustum& fr = scene.camera.frustum;
  const double width = fr.right - fr.left;
  ConditioningFeatures f;
  f.light_near_distance =
      nearcap::to_double(Rational((cs.exact_light(light).z + Rational(fr.near)) / Rational(fr.near)));
  f.coordinate_over_size = coordinate_over_size(scene);
  f.depth_step_over_size = depth_step_over_size(cs);

  f.light_frustum_defined = lf.defined;
  if (!lf.defined) {
    f.l_far_over_width = f.delta_over_width = f.skew = f.l_near_over_l_far = kNaN;
    f.cond_projection = f.cond_light_transform = f.cap_window_error_px = f.cap_window_error_ulp = kNaN;
    return f;
  }
  const double cx = 0.5 * (fr.left + fr.right), cy = 0.5 * (fr.bottom + fr.top);
  const double side = std::hypot(lf.delta.x - cx, lf.delta.y - cy);
  f.l_far_over_width = lf.l_far / width;
  f.delta_over_width = side / width;
  f.skew = side / lf.l_far;
  f.l_near_over_l_far = static_cast<double>(lf.l_near) / lf.l_far;
  f.cond_projection = projection_condition(lf);
  f.cond_light_transform = light_transform_condition(lf);

  // The near-cap pass's window coordinates of occluder vertices, float32 as
  // the vertex program and viewport compute them, against the exact projection.
  const gl::Mat4f view = gl::to_mat4f(scene.camera.view);
  const BoundedVec3& l = cs.light(light);
  const double lx = l.x.v, ly = l.y.v, lz = l.z.v;
  const int w = scene.camera.width, h = scene.camera.height;
  const float half_w = 0.5f * static_cast<float>(w), half_h = 0.5f * static_cast<float>(h);
  for (std::size_t o = 0; o < cs.object_count(); ++o) {
    if (!cs.object(o).occluder) continue;
    const gl::Mat4f modelview = gl::multiply(view, gl::to_mat4f(cs.object(o).object_to_world), arithmetic);
    const gl::Mat4f light_modelview = gl::multiply(lf.modelview, modelview, arithmetic);
    const TriangleMesh& mesh = cs.mesh(o);
    for (VertexIndex v = 0; v < mesh.positions.size(); ++v) {
      const Vec3d& p = cs.vertex_estimate(o, v);
      // The exact projection from the light onto z = -near: l + t (p - l).
      const double t = (-fr.near - lz) / (p.z - lz);
      if (!(t >= 1.0) || !std::isfinite(t)) continue;  // not between the light and the near plane
      const double ex = (lx + t * (p.x - lx) - fr.left) / width * w;
      const double ey = (ly + t * (p.y - ly) - fr.bottom) / (fr.top - fr.bottom) * h;
      if (ex < -w || ex > 2.0 * w || ey < -h || ey > 2.0 * h) continue;
      const Vec3d& q = mesh.positions[v];
      const gl::Vec4f object{static_cast<float>(q.x), static_cast<float>(q.y), static_cast<float>(q.z), 1.0f};
      const gl::Vec4f clip =
          gl::transform(lf.projection, gl::transform(light_modelview, object, arithmetic), arithmetic);
      if (!(clip.w > 0.0f)) continue;
      const float fx = (clip.x / clip.w + 1.0f) * half_w, fy = (clip.y / clip.w + 1.0f) * half_h;
      const double err = std::max(std::fabs(fx - ex), std::fabs(fy - ey));
      const double ulps = err / float_ulp(std::max(w, h));
      f.cap_window_error_px = std::max(f.cap_window_error_px, err);
      f.cap_window_error_ulp = std::max(f.cap_window_error_ulp, ulps);
      ++f.cap_vertices;
    }
  }
  return f;
}

double projection_condition(const gl::LightFrustum& lf) { return condition_number(entries(lf.projection)); }

double light_transform_condition(const gl::LightFrustum& lf) {
  return condition_number(product(entries(lf.projection), entries(lf.modelview)));
}

}  // namespace nearcap::analysis
