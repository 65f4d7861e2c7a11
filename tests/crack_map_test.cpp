// The judgement of a frame against the exact reference (judge/crack_map.hpp)
// on hand-made pixels: a rasterized frame's stencil is compared with the
// count mod 256, a ray-traced frame's status with the count's sign alone.
#include "nearcap/judge/crack_map.hpp"
#include "nearcap/raytrace/shadow_ray_tracer.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

namespace nearcap {
namespace {

// One row of six pixels: nothing seen; counts 0, 2, 257 (1 mod 256), 3 and 1.
PixelReference six_pixels() {
  PixelReference ref;
  ref.width = 6;
  ref.height = 1;
  ref.stencil = {PixelReference::kNothingSeen, 0, 2, 257, 3, 1};
  ref.cap = {0, 0, 1, 0, 0, 0};
  ref.object = {-1, 0, 0, 0, 0, 0};
  ref.face = {0, 0, 0, 0, 0, 0};
  return ref;
}

TEST(CrackMap, AStencilIsComparedWithTheCountMod256) {
  const PixelReference ref = six_pixels();
  gl::ShadowFrame frame;
  frame.method = gl::ShadowMethod::ZFail;
  frame.width = 6;
  frame.height = 1;
  frame.object = {-1, 0, 0, 0, 0, 1};
  frame.stencil = {0, 0, 1, 1, 0, 1};
  frame.near_cap = {0, 0, 1, 0, 1, 0};
  const CrackReport r = judge_frame(frame, ref);
  EXPECT_EQ(r.method, "zfail");
  EXPECT_EQ(r.verdict,
            (std::vector<PixelVerdict>{PixelVerdict::NothingSeen, PixelVerdict::Right, PixelVerdict::CountOnly,
                                       PixelVerdict::Right, PixelVerdict::WrongLit, PixelVerdict::VisibilityMismatch}));
  EXPECT_EQ(r.pixels_seen, 5u);
  EXPECT_EQ(r.wrong, 1u);
  EXPECT_EQ(r.wrong_lit, 1u);
  EXPECT_EQ(r.wrong_shadowed, 0u);
  EXPECT_EQ(r.count_mismatch, 2u);  // the count-only pixel and the wrong one
  EXPECT_EQ(r.visibility_mismatch, 1u);
  ASSERT_TRUE(r.cap_mismatch.has_value());  // a whole-scene near-cap pass is compared too
  EXPECT_EQ(*r.cap_mismatch, 1u);
  EXPECT_EQ(r.cap_wrong, (std::vector<bool>{false, false, false, false, true, false}));
}

TEST(CrackMap, AShadowStatusIsComparedWithTheCountsSignAlone) {
  const PixelReference ref = six_pixels();
  raytrace::RaytraceFrame frame;
  frame.width = 6;
  frame.height = 1;
  frame.object = {-1, 0, 0, 0, 0, 1};
  frame.face = {0, 0, 0, 0, 0, 0};
  frame.shadowed = {0, 1, 1, 1, 0, 1};
  const CrackReport r = judge_raytrace_frame(frame, ref);
  EXPECT_EQ(r.method, "raytrace");
  EXPECT_EQ(r.verdict,
            (std::vector<PixelVerdict>{PixelVerdict::NothingSeen, PixelVerdict::WrongShadowed, PixelVerdict::Right,
                                       PixelVerdict::Right, PixelVerdict::WrongLit, PixelVerdict::VisibilityMismatch}));
  EXPECT_EQ(r.pixels_seen, 5u);
  EXPECT_EQ(r.wrong_lit, 1u);
  EXPECT_EQ(r.wrong_shadowed, 1u);
  EXPECT_EQ(r.count_mismatch, r.wrong);  // no count to differ where the status is right
  EXPECT_FALSE(r.cap_mismatch.has_value());
  EXPECT_TRUE(r.cap_wrong.empty());
}

}  // namespace
}  // namespace nearcap
