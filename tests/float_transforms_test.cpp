// The float32 vertex transform: each clip-space component is its matrix row
// against the vertex in the reference order, x*m0 + y*m1 + z*m2 + w*m3 rounded
// left to right (or the fma chain), bit for bit, whichever way the transform
// computes its four rows at once.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "nearcap/gl/float_transforms.hpp"
#include "nearcap/gl/shadow_vertex_programs.hpp"

namespace nearcap::gl {
namespace {

// The row in the reference order, written out.
float reference_row(const Mat4f& m, int r, const Vec4f& v, Arithmetic arithmetic) {
  if (arithmetic == Arithmetic::Fused) {
    float s = m.at(r, 0) * v.x;
    s = std::fmaf(m.at(r, 1), v.y, s);
    s = std::fmaf(m.at(r, 2), v.z, s);
    return std::fmaf(m.at(r, 3), v.w, s);
  }
  float s = m.at(r, 0) * v.x;
  s = s + m.at(r, 1) * v.y;
  s = s + m.at(r, 2) * v.z;
  return s + m.at(r, 3) * v.w;
}

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(FloatTransform, EachComponentIsItsRowInTheReferenceOrder) {
  std::mt19937 rng(20261204);
  // Mantissas with any low bits and exponents over a wide range, so that the
  // order of the sums shows in the last bits; some entries repeated with the
  // opposite sign, so that partial sums cancel.
  std::uniform_real_distribution<float> mantissa(-1.0f, 1.0f);
  std::uniform_int_distribution<int> exponent(-20, 20), pick(0, 15);
  auto value = [&] { return std::ldexp(mantissa(rng), exponent(rng)); };
  std::size_t order_matters = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    Mat4f m;
    for (float& x : m.m) x = value();
    if (trial % 3 == 0) m.m[static_cast<std::size_t>(pick(rng))] = -m.m[static_cast<std::size_t>(pick(rng))];
    const Vec4f v{value(), value(), value(), trial % 4 == 0 ? 0.0f : 1.0f};
    for (Arithmetic arithmetic : {Arithmetic::Separate, Arithmetic::Fused}) {
      const Vec4f c = transform(m, v, arithmetic);
      const float got[4] = {c.x, c.y, c.z, c.w};
      for (int r = 0; r < 4; ++r) {
        const float want = reference_row(m, r, v, arithmetic);
        ASSERT_TRUE(same_bits(got[r], want))
            << "trial " << trial << ", row " << r << ": " << got[r] << " against " << want;
        ASSERT_TRUE(same_bits(transform_row(m, r, v, arithmetic), want)) << "trial " << trial << ", row " << r;
        // Summed right to left instead: how often the order is visible.
        const float reversed = ((m.at(r, 3) * v.w + m.at(r, 2) * v.z) + m.at(r, 1) * v.y) + m.at(r, 0) * v.x;
        order_matters += arithmetic == Arithmetic::Separate && !same_bits(reversed, want);
      }
    }
  }
  EXPECT_GT(order_matters, 1000u) << "inputs whose sum depends on its order";
}

// The vertex programs run on a whole draw give each vertex's own run.
TEST(FloatTransform, ProgramsOnADrawAreEachVertexsRun) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> coordinate(-3.0f, 3.0f);
  ShadowUniforms u;
  for (Mat4f* m : {&u.modelview_projection, &u.light_modelview, &u.light_projection})
    for (float& x : m->m) x = coordinate(rng);
  u.light_position = {0.5f, 2.0f, -1.0f};
  std::vector<ShadowVertex> inputs;
  for (int k = 0; k < 400; ++k)
    inputs.push_back({coordinate(rng), coordinate(rng), coordinate(rng), static_cast<float>(k % 5)});
  for (VertexProgram p : {VertexProgram::Extrusion, VertexProgram::Figure7, VertexProgram::NearCap})
    for (Arithmetic arithmetic : {Arithmetic::Separate, Arithmetic::Fused}) {
      u.arithmetic = arithmetic;
      const std::vector<Vec4f> batch = run_vertex_program(p, u, inputs);
      ASSERT_EQ(batch.size(), inputs.size());
      for (std::size_t k = 0; k < inputs.size(); ++k) {
        const Vec4f one = run_vertex_program(p, u, inputs[k]);
        EXPECT_EQ(std::memcmp(&batch[k], &one, sizeof one), 0) << to_string(p) << ", vertex " << k;
      }
    }
}

}  // namespace
}  // namespace nearcap::gl
