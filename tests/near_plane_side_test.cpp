// near_plane_side_of_box (gl/near_plane_cap.hpp) at its boundary: a box
// says +1 or -1 only when every vertex the float32 program makes from it
// has that sign of near-plane distance, bit for bit as the pipeline
// computes it; a vertex on the plane or one float step from it is too
// close to call.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>

#include "nearcap/gl/clipping.hpp"
#include "nearcap/gl/near_plane_cap.hpp"

namespace nearcap {
namespace {

using gl::DepthMapping;
using gl::Mat4f;
using gl::Vec4f;

// The near-plane distance the pipeline computes for the object-space
// vertex p (w = 1) or the direction p - light (w = 0): the coordinates
// rounded to float, the light subtracted in float, the z and w rows in
// float32 (shadow_vertex_programs.cpp, extrusion_input).
float pipeline_distance(const Mat4f& m, const Vec3d& p, double w, const Vec3d& light, DepthMapping mapping,
                        gl::Arithmetic arithmetic) {
  Vec4f in{static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z), 1.0f};
  if (w == 0) {
    const float lx = static_cast<float>(light.x), ly = static_cast<float>(light.y), lz = static_cast<float>(light.z);
    in = {in.x - lx, in.y - ly, in.z - lz, 0.0f};
  }
  Vec4f clip;
  clip.z = gl::transform_row(m, 2, in, arithmetic);
  clip.w = gl::transform_row(m, 3, in, arithmetic);
  return gl::near_plane_distance(clip, mapping);
}

// z + w = x - 10^6: the plane x = 10^6, where float32 steps are 1/16.
Mat4f plane_at_a_million() {
  Mat4f m{};
  m.at(2, 0) = 1.0f;
  m.at(2, 3) = -1000001.0f;
  m.at(3, 3) = 1.0f;
  return m;
}

int side_of_point(const Mat4f& m, double x) { return gl::near_plane_side_of_box(m, {x, 0, 0}, {x, 0, 0}, 1.0); }

TEST(NearPlaneSide, AVertexOnThePlaneOrOneFloatStepFromItIsTooCloseToCall) {
  const Mat4f m = plane_at_a_million();
  const Vec3d none{};
  const float step = std::nextafter(1e6f, 2e6f) - 1e6f;
  ASSERT_EQ(step, 0.0625f);
  // On the plane: distance 0 in float too.
  EXPECT_EQ(pipeline_distance(m, {1e6, 0, 0}, 1, none, DepthMapping::Standard, gl::Arithmetic::Separate), 0.0f);
  EXPECT_EQ(side_of_point(m, 1e6), 0);
  // One float step beyond and in front: the float distance has the sign,
  // but the certified bound (about 6 2^-24 of 2 10^6) is wider than a step.
  EXPECT_GT(pipeline_distance(m, {1e6 + step, 0, 0}, 1, none, DepthMapping::Standard, gl::Arithmetic::Separate), 0.0f);
  EXPECT_EQ(side_of_point(m, 1e6 + step), 0);
  EXPECT_LT(pipeline_distance(m, {1e6 - step, 0, 0}, 1, none, DepthMapping::Standard, gl::Arithmetic::Separate), 0.0f);
  EXPECT_EQ(side_of_point(m, 1e6 - step), 0);
  // Less than half a step beyond: the input rounds onto the plane, float
  // distance 0, so the exact sign (+) must not be reported.
  EXPECT_EQ(pipeline_distance(m, {1e6 + 0.03, 0, 0}, 1, none, DepthMapping::Standard, gl::Arithmetic::Separate), 0.0f);
  EXPECT_EQ(side_of_point(m, 1e6 + 0.03), 0);
  // Far enough (16 steps, 1): decided.
  EXPECT_EQ(side_of_point(m, 1e6 + 1), 1);
  EXPECT_EQ(side_of_point(m, 1e6 - 1), -1);
}

TEST(NearPlaneSide, DirectionsCountTheLightsRounding) {
  // Directions p - l with z + w = x: a vertex at 10^6 + 0.04 rounds to
  // 10^6 + 1/16, the light's x, so the program's direction is 0 where the
  // exact one is -0.0225.  Only with the light's size in the bound is that
  // too close to call.
  Mat4f m{};
  m.at(2, 0) = 1.0f;
  const Vec3d p{1e6 + 0.04, 0, 0}, light{1e6 + 0.0625, 0, 0};
  ASSERT_EQ(pipeline_distance(m, p, 0, light, DepthMapping::Standard, gl::Arithmetic::Separate), 0.0f);
  const Vec3d d = p - light;
  EXPECT_EQ(gl::near_plane_side_of_box(m, d, d, 0.0, DepthMapping::Standard, light), 0);
  // The same direction from a light at the origin is far from the plane
  // relative to its size: decided.
  EXPECT_EQ(gl::near_plane_side_of_box(m, d, d, 0.0), -1);
}

TEST(NearPlaneSide, ReversedDepthUsesWMinusZ) {
  // w - z = 10^6 - x: beyond the plane for x < 10^6.
  Mat4f m{};
  m.at(2, 0) = 1.0f;
  m.at(3, 3) = 1e6f;
  EXPECT_EQ(gl::near_plane_side_of_box(m, {0, 0, 0}, {1e6 - 1, 0, 0}, 1.0, DepthMapping::Reversed), 1);
  EXPECT_EQ(gl::near_plane_side_of_box(m, {0, 0, 0}, {1e6 - 0.0625, 0, 0}, 1.0, DepthMapping::Reversed), 0);
  EXPECT_EQ(gl::near_plane_side_of_box(m, {1e6 + 1, 0, 0}, {2e6, 0, 0}, 1.0, DepthMapping::Reversed), -1);
}

// Random float matrices, boxes straddling or near the plane (a random
// point moved along the row to within a few certified bounds of it), and
// lights: whenever the box is decided, every vertex in it (corners and
// random points) has that sign of float distance, separate or fused.
RC_GTEST_PROP(NearPlaneSide, ADecidedBoxHasThatSignAtEveryVertex, ()) {
  auto coordinate = [] {
    return *rc::gen::inRange(-1000000, 1000001) / 64.0 * std::pow(2.0, *rc::gen::inRange(-8, 12));
  };
  Mat4f m{};
  for (int r = 2; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m.at(r, c) = static_cast<float>(*rc::gen::inRange(-1000, 1001) / 256.0);
  const double w = *rc::gen::inRange(0, 2);
  const DepthMapping mapping = *rc::gen::inRange(0, 2) ? DepthMapping::Standard : DepthMapping::Reversed;
  const double s = mapping == DepthMapping::Standard ? 1.0 : -1.0;
  const Vec3d light = w == 0 ? Vec3d{static_cast<float>(coordinate()), static_cast<float>(coordinate()),
                                     static_cast<float>(coordinate())}
                             : Vec3d{};
  const double row[3] = {s * m.at(2, 0) + m.at(3, 0), s * m.at(2, 1) + m.at(3, 1), s * m.at(2, 2) + m.at(3, 2)};
  const double offset = w * (s * m.at(2, 3) + m.at(3, 3));
  const double norm2 = row[0] * row[0] + row[1] * row[1] + row[2] * row[2];
  RC_PRE(norm2 > 0);
  // The box's centre (in the function's coordinates: p - light for
  // directions) at exact distance t from the plane, t a small multiple of
  // the products' size.
  Vec3d c{coordinate(), coordinate(), coordinate()};
  const double d0 = row[0] * c.x + row[1] * c.y + row[2] * c.z + offset;
  const double scale =
      std::fabs(row[0] * c.x) + std::fabs(row[1] * c.y) + std::fabs(row[2] * c.z) + std::fabs(offset) + 1;
  const double t = *rc::gen::inRange(-400, 401) * 0x1p-24 * scale / 16;
  const double shift = (t - d0) / norm2;
  c = {c.x + shift * row[0], c.y + shift * row[1], c.z + shift * row[2]};
  const double half = *rc::gen::inRange(0, 3) * 0x1p-24 * scale / std::sqrt(norm2);
  const Vec3d lo{c.x - half, c.y - half, c.z - half}, hi{c.x + half, c.y + half, c.z + half};
  const int side = gl::near_plane_side_of_box(m, lo, hi, w, mapping, light);
  RC_TAG(side);
  if (side == 0) return;
  for (int k = 0; k < 12; ++k) {
    Vec3d q = lo;
    if (k < 8) {
      q = {(k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z};
    } else {
      const double f[3] = {*rc::gen::inRange(0, 1025) / 1024.0, *rc::gen::inRange(0, 1025) / 1024.0,
                           *rc::gen::inRange(0, 1025) / 1024.0};
      q = {lo.x + f[0] * (hi.x - lo.x), lo.y + f[1] * (hi.y - lo.y), lo.z + f[2] * (hi.z - lo.z)};
    }
    const Vec3d p = w == 0 ? q + light : q;  // the vertex the program reads
    for (gl::Arithmetic a : {gl::Arithmetic::Separate, gl::Arithmetic::Fused}) {
      const float d = pipeline_distance(m, p, w, light, mapping, a);
      const bool that_sign = side > 0 ? d > 0 : d < 0;
      RC_ASSERT(that_sign);
    }
  }
}

}  // namespace
}  // namespace nearcap
