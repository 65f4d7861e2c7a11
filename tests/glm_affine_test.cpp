// src/gl/glm_affine.hpp: the glm form of an Affine3d maps a point as the
// affine map does, and its float32 form rounds each entry once.
#include "../src/gl/glm_affine.hpp"

#include <gtest/gtest.h>

namespace nearcap {
namespace {

// Small integers and halves: every product and sum below is exact in double,
// so the two forms agree bit for bit.
Affine3d sample_map() {
  Affine3d a;
  a.rows = {{{2, -1, 0.5, 3}, {0, 1.5, -2, -4}, {1, 0, 3, 0.25}}};
  return a;
}

TEST(GlmAffine, MapsAPointAsTheAffineMapDoes) {
  const Affine3d a = sample_map();
  const Vec3d p{1.5, -2, 4};
  const glm::dvec4 q = gl::to_glm(a) * glm::dvec4(p.x, p.y, p.z, 1.0);
  const Vec3d expected = a.apply(p);
  EXPECT_EQ(q.x, expected.x);
  EXPECT_EQ(q.y, expected.y);
  EXPECT_EQ(q.z, expected.z);
  EXPECT_EQ(q.w, 1.0);
}

TEST(GlmAffine, TheFloatFormRoundsEachEntryOnce) {
  Affine3d a = sample_map();
  a.rows[1][3] = 0.1;  // not a float32
  const glm::mat4 m = gl::to_glm_float(a);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) EXPECT_EQ(m[c][r], static_cast<float>(a.rows[r][c])) << r << ", " << c;
  EXPECT_EQ(m[0][3], 0.0f);
  EXPECT_EQ(m[3][3], 1.0f);
}

}  // namespace
}  // namespace nearcap
