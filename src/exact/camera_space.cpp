// Camera-space geometry: exact maps, certified estimates.
//
// The composed map C = view * object_to_world has rational entries (products
// and sums of doubles).  Its BoundedDouble estimate is evaluated from the same
// doubles, so each vertex estimate C v carries a certified bound; the exact
// vertex is recomputed from the rational C when a filter fails.
#include "nearcap/exact/camera_space.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <mutex>
#include <optional>
#include <string_view>

namespace nearcap {

std::string_view to_string(Predicate p) {
  switch (p) {
    case Predicate::LightFacing:
      return "light_facing";
    case Predicate::NearPlaneSide:
      return "near_plane_side";
    case Predicate::SegmentCrossing:
      return "segment_crossing";
    case Predicate::RayHit:
      return "ray_hit";
    case Predicate::ShadowCrossing:
      return "shadow_crossing";
    case Predicate::Arrangement:
      return "arrangement";
    case Predicate::kCount:
      break;
  }
  return "unknown";
}

RationalAffine RationalAffine::from(const Affine3d& a) {
  RationalAffine r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j) r.m[i][j] = a.rows[i][j];
  return r;
}

RationalAffine RationalAffine::then(const RationalAffine& outer) const {
  RationalAffine r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j) {
      Rational s = j == 3 ? outer.m[i][3] : Rational(0);
      for (int k = 0; k < 3; ++k) s += outer.m[i][k] * m[k][j];
      r.m[i][j] = s;
    }
  return r;
}

RationalVec3 RationalAffine::apply(const RationalVec3& p) const {
  RationalVec3 r;
  for (int i = 0; i < 3; ++i) r[i] = m[i][0] * p.x + m[i][1] * p.y + m[i][2] * p.z + m[i][3];
  return r;
}

namespace {

// The determinant of an affine map's linear part (rows of [3][4]), in T's
// arithmetic: exact for Rational, with a certified bound for BoundedDouble.
template <class T>
T linear_determinant(const T (&m)[3][4]) {
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
         m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

// Estimate of outer * inner entries from the exact doubles of both maps.
struct BoundedAffine {
  BoundedDouble m[3][4];
  BoundedVec3 apply(const Vec3d& p) const {
    BoundedVec3 r;
    for (int i = 0; i < 3; ++i)
      r[i] = m[i][0] * BoundedDouble(p.x) + m[i][1] * BoundedDouble(p.y) + m[i][2] * BoundedDouble(p.z) + m[i][3];
    return r;
  }
};

BoundedAffine compose_bounded(const Affine3d& outer, const Affine3d& inner) {
  BoundedAffine r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j) {
      BoundedDouble s = j == 3 ? BoundedDouble(outer.rows[i][3]) : BoundedDouble(0.0);
      for (int k = 0; k < 3; ++k) s += BoundedDouble(outer.rows[i][k]) * BoundedDouble(inner.rows[k][j]);
      r.m[i][j] = s;
    }
  return r;
}

}  // namespace

Sign RationalAffine::linear_determinant_sign() const { return sign_of(linear_determinant(m)); }

CameraSpaceScene::CameraSpaceScene(const Scene& scene) : scene_(&scene) {
  objects_.resize(scene.objects.size());
  for (std::size_t o = 0; o < scene.objects.size(); ++o) {
    const SceneObject& obj = scene.objects[o];
    ObjectData& d = objects_[o];
    const BoundedAffine approx = compose_bounded(scene.camera.view, obj.object_to_world);
    // The bounded determinant holds the exact map's within its bound.
    const std::optional<Sign> handedness = linear_determinant(approx.m).sign();
    d.handedness = handedness ? *handedness : exact().to_camera[o].linear_determinant_sign();
    // Plain-double transform with one certified bound for all vertices:
    // coordinate i is sum_j C_ij v_j + C_i3 with each C_ij known to within
    // e_C and four roundings (three products, three sums: gamma_4 covers them),
    // so |error| <= (max e_C + gamma_4 max|C|) (|v|_1 + 1).
    double c[3][4], e_c = 0, c_max = 0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 4; ++j) {
        c[i][j] = approx.m[i][j].v;
        e_c = std::fmax(e_c, approx.m[i][j].e);
        c_max = std::fmax(c_max, std::fabs(c[i][j]));
      }
    // One pass over the vertices: |v|_1 + 1 and each coordinate's largest
    // |estimate|, each a running maximum of its own (a max is exact, so
    // the order does not change it).
    const auto& positions = obj.mesh->positions;
    d.estimates.resize(positions.size());
    double v1 = 1.0;
    std::array<double, 3> max_abs{};
    for (std::size_t v = 0; v < positions.size(); ++v) {
      const Vec3d& p = positions[v];
      v1 = std::max(v1, std::fabs(p.x) + std::fabs(p.y) + std::fabs(p.z) + 1.0);
      const double x = c[0][0] * p.x + c[0][1] * p.y + c[0][2] * p.z + c[0][3];
      const double y = c[1][0] * p.x + c[1][1] * p.y + c[1][2] * p.z + c[1][3];
      const double z = c[2][0] * p.x + c[2][1] * p.y + c[2][2] * p.z + c[2][3];
      d.estimates[v] = {x, y, z};
      max_abs[0] = std::max(max_abs[0], std::fabs(x));
      max_abs[1] = std::max(max_abs[1], std::fabs(y));
      max_abs[2] = std::max(max_abs[2], std::fabs(z));
    }
    constexpr double kGamma4 = 4 * 0x1p-53 / (1 - 4 * 0x1p-53);
    d.max_error = (e_c + kGamma4 * c_max) * v1 * (1 + 0x1p-50);
    d.max_abs = std::max({max_abs[0], max_abs[1], max_abs[2]}) + d.max_error;
  }
  const Affine3d identity = Affine3d::identity();
  const BoundedAffine view_approx = compose_bounded(scene.camera.view, identity);
  for (const Light& l : scene.lights) lights_.push_back(view_approx.apply(l.position));
}

const CameraSpaceScene::ExactData& CameraSpaceScene::exact() const {
  std::call_once(exact_once_, [this] {
    const RationalAffine view = RationalAffine::from(scene_->camera.view);
    for (const SceneObject& obj : scene_->objects)
      exact_.to_camera.push_back(RationalAffine::from(obj.object_to_world).then(view));
    for (const Light& l : scene_->lights) exact_.lights.push_back(view.apply(to_rational(l.position)));
  });
  return exact_;
}

RationalVec3 CameraSpaceScene::exact_vertex(std::size_t o, VertexIndex v) const {
  return exact().to_camera[o].apply(to_rational(scene_->objects[o].mesh->positions[v]));
}

}  // namespace nearcap
