// ZF+ (ZFailFar::FarCap, SwitchClamp::FarCap; gl/near_plane_cap.hpp): Z-fail
// with a finite far plane, no depth clamp, and the far-plane cap its clipped
// volume leaves.  The cap's edges are the faces' own far edges (the far
// plane clipped first), the cap makes Z-fail right where the far plane cuts
// the volumes, as far-only depth clamp does, and it is the case-D switch
// that real llvmpipe draws right (GL_DEPTH_CLAMP's is wrong there).
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <string>

#include "llvmpipe_fixture.hpp"
#include "nearcap/analysis/hard_case_sampler.hpp"
#include "nearcap/error.hpp"
#include "nearcap/exact/camera_space.hpp"
#include "nearcap/exact/pixel_reference.hpp"
#include "nearcap/gl/clipping.hpp"
#include "nearcap/gl/near_plane_cap.hpp"
#include "nearcap/gl/shadow_methods.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/judge/crack_map.hpp"
#include "nearcap/render/gl_frame_replay.hpp"
#include "support/sampled_scenes.hpp"

namespace nearcap {
namespace {

bool same_bits(const gl::Vec4f& a, const gl::Vec4f& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Triangles across the far plane, some reaching behind the eye: every
// vertex of a far-plane edge that clip_to_far_plane leaves, in front of the
// near plane, is a vertex of clip_triangle's polygon with the far plane
// first, bit for bit.
TEST(FarPlaneCap, ItsEdgesAreTheFacesFarEdges) {
  std::mt19937 rng(12);
  std::uniform_real_distribution<float> xy(-2.0f, 2.0f), z(-3.0f, 3.0f), w(-0.5f, 2.0f);
  gl::ClipSettings settings;
  settings.far_first = true;
  std::size_t checked = 0;
  for (int k = 0; k < 20000; ++k) {
    const gl::Vec4f a{xy(rng), xy(rng), z(rng), w(rng)}, b{xy(rng), xy(rng), z(rng), w(rng)},
        c{xy(rng), xy(rng), z(rng), w(rng)};
    const gl::NearClippedPolygon far = gl::clip_to_far_plane(a, b, c);
    const std::vector<gl::Vec4f> poly = gl::clip_triangle(a, b, c, settings);
    for (std::size_t i = 0; i < far.vertices.size(); ++i) {
      const gl::Vec4f& v = far.vertices[i];
      // Only far-plane vertices the near plane and the guard band keep.
      if (!far.on_near_plane[i] || !(v.z + v.w > 0) || !(std::fabs(v.x) < 8192 * v.w) || !(std::fabs(v.y) < 8192 * v.w))
        continue;
      bool found = false;
      for (const gl::Vec4f& p : poly) found = found || same_bits(p, v);
      EXPECT_TRUE(found) << "triangle " << k;
      ++checked;
    }
  }
  EXPECT_GT(checked, 5000u);
}

struct Judged {
  Scene scene;
  PixelReference ref;
};

Judged judged(const std::string& name) {
  Judged j;
  j.scene = load_scene(std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/" + name);
  const CameraSpaceScene cs(j.scene);
  j.ref = compute_pixel_reference(cs, 0);
  return j;
}

std::size_t wrong(const Judged& j, gl::ShadowMethod m, gl::ZFailFar far) {
  gl::EmulationSettings s;
  s.zfail_far = far;
  s.switch_clamp = far == gl::ZFailFar::FarCap ? gl::SwitchClamp::FarCap : gl::SwitchClamp::DepthClampFar;
  return judge_frame(gl::render_shadow_frame(j.scene, 0, m, s), j.ref).wrong;
}

// On the bundled scenes, ZF+ is as right as far-only depth clamp (both
// count every volume the far plane cuts), for Z-fail and for ZP+ corrected's
// case-D switch.
TEST(FarPlaneCap, AsRightAsFarOnlyClampOnTheBundledScenes) {
  for (const char* name : {"default.json", "room.json", "twisted.json", "case_d.json", "light_on_near_plane.json",
                           "near_split.json", "far_grazing.json", "exact_camera.json"}) {
    const Judged j = judged(name);
    for (gl::ShadowMethod m : {gl::ShadowMethod::ZFail, gl::ShadowMethod::ZPPlusCorrected}) {
      SCOPED_TRACE(std::string(name) + ", " + std::string(gl::to_string(m)));
      const std::size_t far_cap = wrong(j, m, gl::ZFailFar::FarCap);
      EXPECT_LE(far_cap, wrong(j, m, gl::ZFailFar::DepthClampFar));
      EXPECT_LE(far_cap, 6u);
    }
  }
  // The switch on case_d: GL_DEPTH_CLAMP's near clamp breaks the depth test
  // (README), the far cap does not.
  const Judged d = judged("case_d.json");
  gl::EmulationSettings clamp;
  const gl::ShadowFrame clamped = gl::render_shadow_frame(d.scene, 0, gl::ShadowMethod::ZPPlusCorrected, clamp);
  ASSERT_FALSE(clamped.zfail_objects.empty());  // case D: the switch
  EXPECT_GT(judge_frame(clamped, d.ref).wrong, 1000u);
  EXPECT_LE(wrong(d, gl::ShadowMethod::ZPPlusCorrected, gl::ZFailFar::FarCap), 1u);
}

// A slice of the hard-case sampler: ZF+ is never wrong on more than two
// pixels more than far-only clamp in a frame (the cap's fan and the clamped
// faces round differently at the far plane).
TEST(FarPlaneCap, OnASliceOfTheSampler) {
  const analysis::HardCaseSampler sampler(test::bundled_sampler_spec(7));
  std::size_t frames = 0, far_cap_wrong = 0, clamp_far_wrong = 0;
  test::for_each_sampled_scene(sampler, 200, [&](const Scene& scene, const analysis::HardCase& sample) {
    const CameraSpaceScene cs(scene);
    for (std::size_t light = 0; light < scene.lights.size(); ++light) {
      PixelReference ref;
      try {
        ref = compute_pixel_reference(cs, light);
      } catch (const Error&) {
        continue;
      }
      gl::EmulationSettings cap, clamp_far;
      cap.zfail_far = gl::ZFailFar::FarCap;
      clamp_far.zfail_far = gl::ZFailFar::DepthClampFar;
      std::size_t a = 0, b = 0;
      try {
        a = judge_frame(gl::render_shadow_frame(scene, light, gl::ShadowMethod::ZFail, cap), ref).wrong;
        b = judge_frame(gl::render_shadow_frame(scene, light, gl::ShadowMethod::ZFail, clamp_far), ref).wrong;
      } catch (const Error&) {
        continue;
      }
      ++frames;
      far_cap_wrong += a;
      clamp_far_wrong += b;
      EXPECT_LE(a, b + 2) << "sample " << sample.index << " light " << light;
    }
  });
  std::printf("[ ZF+      ] %zu frames: %zu wrong pixels with the far cap, %zu with far-only clamp\n", frames,
              far_cap_wrong, clamp_far_wrong);
  EXPECT_GT(frames, 150u);
  // Boundary noise within the policy issue's 10 % (on 3,000 cases of seed 7:
  // 5,732 against 5,737, README).
  EXPECT_LE(far_cap_wrong * 10, clamp_far_wrong * 11);
}

// On llvmpipe: ZP+ corrected's case-D switch with the far cap is the
// emulation's frame pixel for pixel, and right but for a pixel; so is its
// switch with far-only clamp, which llvmpipe (no GL_AMD_depth_clamp_separate)
// draws with GL_DEPTH_CLAMP and the near plane as a gl_ClipDistance (with
// the llvmpipe model's clipper), where GL_DEPTH_CLAMP alone is wrong on
// thousands of pixels.
class FarPlaneCapGlTest : public test::LlvmpipeTest {};

TEST_F(FarPlaneCapGlTest, TheCaseDSwitchOnLlvmpipe) {
  for (const char* name : {"case_d.json", "light_on_near_plane.json"})
    for (gl::SwitchClamp clamp :
         {gl::SwitchClamp::FarCap, gl::SwitchClamp::DepthClampFar, gl::SwitchClamp::DepthClamp}) {
      SCOPED_TRACE(std::string(name) + ", " + std::string(gl::to_string(clamp)));
      const Judged j = judged(name);
      gl::EmulationSettings s;
      s.record_draws = true;
      s.switch_clamp = clamp;
      if (clamp != gl::SwitchClamp::FarCap) s.raster = gl::llvmpipe_model(s.raster);
      const gl::ShadowFrame f = gl::render_shadow_frame(j.scene, 0, gl::ShadowMethod::ZPPlusCorrected, s);
      ASSERT_TRUE(!f.zfail_objects.empty() || !f.fallback.empty());  // the switch: case D, or no light frustum
      render::GlFrameReplay replay(f.width, f.height, s.depth);
      if (clamp == gl::SwitchClamp::DepthClampFar && replay.has_far_only_clamp()) continue;
      const render::ReplayedFrame real = replay.replay(f.draws);
      EXPECT_EQ(render::compare(real, f).stencil, 0u);
      gl::ShadowFrame as_real = f;
      as_real.stencil = real.stencil;
      const std::size_t wrong = judge_frame(as_real, j.ref).wrong;
      if (clamp == gl::SwitchClamp::DepthClamp)
        EXPECT_GT(wrong, 1000u);
      else
        EXPECT_LE(wrong, 1u);
    }
}

}  // namespace
}  // namespace nearcap
