// ZP+'s light frustum (see light_frustum.hpp).
#include "nearcap/gl/light_frustum.hpp"

#include <glm/glm.hpp>

#include "nearcap/error.hpp"
#include "nearcap/exact/light_pyramid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace nearcap::gl {
namespace {

// Closest point of triangle abc to p (Ericson, Real-Time Collision Detection 5.1.5).
Vec3d closest_point_on_triangle(const Vec3d& p, const Vec3d& a, const Vec3d& b, const Vec3d& c) {
  const Vec3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3d bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + (d1 / (d1 - d3)) * ab;
  const Vec3d cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double denom = 1.0 / (va + vb + vc);
  return a + (vb * denom) * ab + (vc * denom) * ac;
}

constexpr double kMaxNearRatio = 0.5;

double length(const Vec3d& v) { return std::sqrt(dot(v, v)); }

bool all_finite(const Mat4f& m) {
  return std::all_of(m.m.begin(), m.m.end(), [](float v) { return std::isfinite(v); });
}

}  // namespace

Vec4f light_in_camera_space(const Scene& scene, std::size_t light) {
  glm::mat4 view(1.0f);  // column-major, as engine_classification.cpp builds it
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) view[c][r] = static_cast<float>(scene.camera.view.rows[r][c]);
  const Vec3d& p = scene.lights[light].position;
  const glm::vec4 l = view * glm::vec4(static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z), 1.0f);
  return {l.x, l.y, l.z, 1.0f};
}

double distance_to_occluders(const Scene& scene, const Vec3d& p) {
  // In camera space, where d_max is measured: a view with a scale or a shear
  // changes distances, and d / d_max must compare lengths of one space.
  const Affine3d& view = scene.camera.view;
  const Vec3d pc = view.apply(p);
  double best = std::numeric_limits<double>::infinity();
  for (const SceneObject& obj : scene.objects) {
    if (!obj.occluder) continue;
    std::vector<Vec3d> cam(obj.mesh->positions.size());
    for (std::size_t v = 0; v < cam.size(); ++v) cam[v] = view.apply(obj.object_to_world.apply(obj.mesh->positions[v]));
    for (const auto& t : obj.mesh->triangles)
      best = std::min(best, length(pc - closest_point_on_triangle(pc, cam[t[0]], cam[t[1]], cam[t[2]])));
  }
  return best;
}

LightFrustum light_frustum(const Scene& scene, std::size_t light, const LightFrustumChoice& choice) {
  LightFrustum lf;
  const Frustum& f = scene.camera.frustum;
  lf.delta = light_in_camera_space(scene, light);
  const float near = static_cast<float>(f.near);
  const float side = lf.delta.z + near;
  if (side == 0.0f) {
    lf.undefined_reason = "the light lies in the camera's near plane (l_far = 0)";
    return lf;
  }
  lf.alpha = side > 0 ? 1 : -1;
  const float alpha = static_cast<float>(lf.alpha);
  lf.l_far = alpha * side;

  double l_near = 0;
  switch (choice.near_rule) {
    case LightNearRule::PaperRatio: {
      // d and d_max in double and both in camera space: they only have to
      // bound the light pyramid.
      lf.d = distance_to_occluders(scene, scene.lights[light].position);
      const Vec3d l_cam{lf.delta.x, lf.delta.y, lf.delta.z};
      for (double x : {f.left, f.right})
        for (double y : {f.bottom, f.top}) lf.d_max = std::max(lf.d_max, length(Vec3d{x, y, -f.near} - l_cam));
      // The ratio is capped at 1/2 whenever it exceeds 1/2 (not only when
      // d >= d_max, where the paper's l_near would reach l_far): an l_near close
      // to l_far leaves P_l's depth row, (l_near + l_far) / (l_near - l_far),
      // ill-conditioned, and the far plane clips the occluder at the near rectangle.
      l_near = lf.l_far * std::min(lf.d / lf.d_max, kMaxNearRatio);
      break;
    }
    case LightNearRule::ExactMax: {
      const CameraSpaceScene cs(scene);
      AdmissibleLightNear a;
      try {
        a = max_admissible_light_near(cs, light);
      } catch (const Error& e) {
        if (e.kind() != ErrorKind::Degenerate) throw;
        lf.undefined_reason = "the light lies exactly in the camera's near plane (l_far = 0)";
        return lf;
      }
      lf.admissible = a.l_near ? to_double(*a.l_near) : std::numeric_limits<double>::infinity();
      l_near = std::min(lf.admissible, kMaxNearRatio * lf.l_far);
      break;
    }
    case LightNearRule::NearClamp:
      lf.near_clamped = true;
      l_near = kMaxNearRatio * lf.l_far;
      break;
  }
  // Rounded toward zero: never above what the rule admits.
  const double scaled = choice.near_scale * l_near;
  lf.l_near = static_cast<float>(scaled);
  if (static_cast<double>(lf.l_near) > scaled) lf.l_near = std::nextafter(lf.l_near, 0.0f);
  if (!(lf.l_near > 0.0f) || !(lf.l_near < lf.l_far)) {
    lf.undefined_reason = "l_near is not in (0, l_far)";
    return lf;
  }

  // M_l = R_alpha T(-Delta).
  Mat4f& m = lf.modelview;
  m.at(0, 0) = alpha;
  m.at(1, 1) = 1.0f;
  m.at(2, 2) = alpha;
  m.at(3, 3) = 1.0f;
  m.at(0, 3) = -alpha * lf.delta.x;
  m.at(1, 3) = -lf.delta.y;
  m.at(2, 3) = -alpha * lf.delta.z;

  // Delta relative to the near rectangle's centre (zero offset when centred).
  const float width = static_cast<float>(f.right - f.left), height = static_cast<float>(f.top - f.bottom);
  const float dx = lf.delta.x - static_cast<float>(0.5 * (f.left + f.right));
  const float dy = lf.delta.y - static_cast<float>(0.5 * (f.bottom + f.top));
  Mat4f& p = lf.projection;
  if (choice.projection == LightProjection::Composed) {
    // Section 3.1's P_l and M_l with every input in double (Delta = view *
    // light in double), multiplied in double; rounded once, per object, by
    // the caller.  The float32 P_l below is what `paper` uploads, kept for
    // the conditioning features.
    const Vec3d dl = scene.camera.view.apply(scene.lights[light].position);
    const double a = lf.alpha, lfar = a * (dl.z + f.near), ln = double{lf.l_near};
    const double w = f.right - f.left, h = f.top - f.bottom;
    const double ddx = dl.x - 0.5 * (f.left + f.right), ddy = dl.y - 0.5 * (f.bottom + f.top);
    std::array<std::array<double, 4>, 4> pd{}, md{};
    pd[0][0] = 2 * a * lfar / w;
    pd[0][2] = -2 * ddx / w;
    pd[1][1] = 2 * lfar / h;
    pd[1][2] = -2 * ddy / h;
    pd[2][2] = (ln + lfar) / (ln - lfar);
    pd[2][3] = 2 * ln * lfar / (ln - lfar);
    pd[3][2] = -1;
    md[0][0] = a;
    md[1][1] = 1;
    md[2][2] = a;
    md[3][3] = 1;
    md[0][3] = -a * dl.x;
    md[1][3] = -dl.y;
    md[2][3] = -a * dl.z;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c)
        for (int k = 0; k < 4; ++k) lf.composed[r][c] += pd[r][k] * md[k][c];
  }
  if (choice.projection == LightProjection::Paper || choice.projection == LightProjection::Composed ||
      choice.projection == LightProjection::ClippedSides) {
    const float ln = lf.l_near, lfar = lf.l_far;
    p.at(0, 0) = 2.0f * alpha * lfar / width;
    p.at(0, 2) = -2.0f * dx / width;
    p.at(1, 1) = 2.0f * lfar / height;
    p.at(1, 2) = -2.0f * dy / height;
    p.at(2, 2) = (ln + lfar) / (ln - lfar);
    p.at(2, 3) = 2.0f * ln * lfar / (ln - lfar);
    p.at(3, 2) = -1.0f;
  } else if (choice.projection == LightProjection::Rebased) {
    // Origin at the near rectangle's centre: M_l = T(-(cx, cy, -near)).
    m = Mat4f{};
    m.at(0, 0) = m.at(1, 1) = m.at(2, 2) = m.at(3, 3) = 1.0f;
    m.at(0, 3) = -static_cast<float>(0.5 * (f.left + f.right));
    m.at(1, 3) = -static_cast<float>(0.5 * (f.bottom + f.top));
    m.at(2, 3) = near;
    const float ln = lf.l_near, lfar = lf.l_far;
    const float k = (ln + lfar) / (ln - lfar), l = 2.0f * ln * lfar / (ln - lfar);
    p.at(0, 0) = 2.0f * lfar / width;
    p.at(0, 2) = -2.0f * alpha * dx / width;
    p.at(1, 1) = 2.0f * lfar / height;
    p.at(1, 2) = -2.0f * alpha * dy / height;
    p.at(2, 2) = alpha * k;
    p.at(2, 3) = l - k * lfar;
    p.at(3, 2) = -alpha;
    p.at(3, 3) = lfar;
  } else {
    // The far rectangle in the light frame, scaled to the near distance;
    // glFrustum computed in double.  With alpha = -1 the light frame's x is
    // the camera's mirrored, and left > right mirrors it back (the paper's
    // 2 alpha l_far / c_width): NDC x of a near-rectangle point is the camera's.
    const double s = double{lf.l_near} / double{lf.l_far};
    Frustum light_f;
    light_f.left = lf.alpha * (f.left - double{lf.delta.x}) * s;
    light_f.right = lf.alpha * (f.right - double{lf.delta.x}) * s;
    light_f.bottom = (f.bottom - double{lf.delta.y}) * s;
    light_f.top = (f.top - double{lf.delta.y}) * s;
    light_f.near = lf.l_near;
    light_f.far = lf.l_far;
    p = frustum_matrix(light_f);
  }
  if (!all_finite(p) || !all_finite(m)) {
    lf.undefined_reason = "P_l or M_l is not finite in float32";
    return lf;
  }
  lf.defined = true;
  return lf;
}

}  // namespace nearcap::gl
