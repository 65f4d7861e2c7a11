// render/pass_kinds.hpp: each recorded draw's kind, and its counters from the
// emulation's pipeline replayed draw by draw, which must add up to the
// frame's own pass counters (what `nearcap calibrate` pairs with each timed
// pass kind).
#include "nearcap/render/pass_kinds.hpp"

#include <gtest/gtest.h>

#include <array>
#include <memory>
#include <set>
#include <string>

#include "nearcap/error.hpp"
#include "nearcap/gl/shadow_methods.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/render/egl_context.hpp"
#include "nearcap/render/lit_frame.hpp"

namespace nearcap {
namespace {

using gl::PassKind;
using gl::ShadowMethod;

// data/scenes/eye_in_shadow.json at 64x48 (the same 4:3 frustum): the eye in
// the slab's shadow, so ZP+'s near-cap pass draws.
Scene eye_in_shadow() {
  Scene s = load_scene(std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/eye_in_shadow.json");
  s.camera.width = 64;
  s.camera.height = 48;
  return s;
}

std::set<PassKind> kinds_of(const gl::ShadowFrame& f) {
  std::set<PassKind> out;
  for (const gl::DrawCall& d : f.draws) out.insert(render::draw_kind(d));
  return out;
}

void expect_equal(const gl::DrawCounters& a, const gl::DrawCounters& b, const std::string& what) {
  EXPECT_EQ(a.triangles, b.triangles) << what;
  EXPECT_EQ(a.fragments, b.fragments) << what;
  EXPECT_EQ(a.depth_passed, b.depth_passed) << what;
  EXPECT_EQ(a.rasterized, b.rasterized) << what;
  EXPECT_EQ(a.in_view, b.in_view) << what;
}

TEST(PassKinds, EachMethodDrawsItsKinds) {
  const Scene scene = eye_in_shadow();
  gl::EmulationSettings settings;
  settings.record_draws = true;
  gl::EmulationSettings clipped = settings;
  clipped.light_frustum.projection = gl::LightProjection::ClippedSides;
  gl::ShadowFrameBatch batch(scene, 0, settings), clipped_batch(scene, 0, clipped);
  const std::set<PassKind> zpass = kinds_of(batch.render(ShadowMethod::ZPass));
  EXPECT_EQ(zpass, (std::set<PassKind>{PassKind::Depth, PassKind::Sides}));
  const std::set<PassKind> zfail = kinds_of(batch.render(ShadowMethod::ZFail));
  EXPECT_EQ(zfail, (std::set<PassKind>{PassKind::Depth, PassKind::Sides, PassKind::LightCap, PassKind::DarkCap}));
  for (gl::ShadowFrameBatch* b : {&batch, &clipped_batch}) {
    const std::set<PassKind> zpplus = kinds_of(b->render(ShadowMethod::ZPPlus));
    EXPECT_EQ(zpplus, (std::set<PassKind>{PassKind::Depth, PassKind::NearCap, PassKind::Sides}));
  }
  EXPECT_EQ(gl::to_string(PassKind::LightCap), "light_cap");
}

TEST(PassKinds, DrawCountersAddUpToTheFramesPasses) {
  const Scene scene = eye_in_shadow();
  for (const gl::LightProjection projection : {gl::LightProjection::Paper, gl::LightProjection::ClippedSides}) {
    gl::EmulationSettings settings;
    settings.record_draws = true;
    settings.light_frustum.projection = projection;
    gl::ShadowFrameBatch batch(scene, 0, settings);
    for (const ShadowMethod m : {ShadowMethod::ZPass, ShadowMethod::ZFail, ShadowMethod::ZPPlus,
                                 ShadowMethod::ZPPlusCorrected, ShadowMethod::Preload}) {
      const gl::ShadowFrame f = batch.render(m);
      const std::vector<gl::DrawCounters> c = render::draw_counters(f, settings.raster, settings.depth);
      ASSERT_EQ(c.size(), f.draws.size());
      std::array<gl::DrawCounters, 3> by_pass{};  // DrawPass order
      for (std::size_t d = 0; d < c.size(); ++d) {
        EXPECT_EQ(c[d].triangles, f.draws[d].clip_vertices.size() / 3);
        by_pass[static_cast<std::size_t>(f.draws[d].pass)] += c[d];
      }
      const std::string what = std::string(gl::to_string(m)) + " " + std::string(gl::to_string(projection));
      expect_equal(by_pass[0], f.depth_pass, what + " depth");
      expect_equal(by_pass[1], f.cap_pass, what + " near cap");
      expect_equal(by_pass[2], f.volume_pass, what + " volume");
      EXPECT_GT(f.volume_pass.fragments, 0u) << what;
      if (gl::uses_near_cap(m)) {
        EXPECT_GT(f.cap_pass.fragments, 0u) << what;
      }
    }
  }
}

// Drawn kind by kind, the lit frame's stencil is the recorded order's: the
// wrapping increments and decrements commute.  Every kind Z-fail draws is
// timed once per light, after the depth pre-pass.
TEST(PassKinds, DrawingKindByKindLeavesTheStencilAsRecorded) {
  std::unique_ptr<render::EglContext> context;
  try {
    context = std::make_unique<render::EglContext>();
  } catch (const Error& e) {
    GTEST_SKIP() << "no headless OpenGL here: " << e.what();
  }
  const Scene scene = eye_in_shadow();
  gl::EmulationSettings settings;
  settings.record_draws = true;
  for (const ShadowMethod m : {ShadowMethod::ZFail, ShadowMethod::ZPPlus}) {
    const std::vector<gl::ShadowFrame> frames{gl::render_shadow_frame(scene, 0, m, settings)};
    render::LitFrameRenderer renderer;
    render::LitFrameOptions recorded;
    recorded.read_stencils = true;
    render::LitFrameOptions by_kind = recorded;
    by_kind.pass_kind_times = true;
    const render::LitFrame a = renderer.render(scene, frames, settings.depth, recorded);
    const render::LitFrame b = renderer.render(scene, frames, settings.depth, by_kind);
    ASSERT_EQ(a.stencils.size(), 1u);
    ASSERT_EQ(b.stencils.size(), 1u);
    EXPECT_EQ(a.stencils[0], b.stencils[0]) << gl::to_string(m);
    EXPECT_TRUE(a.kind_times.empty());
    std::vector<PassKind> kinds;
    for (const render::KindTime& t : b.kind_times) {
      kinds.push_back(t.kind);
      EXPECT_GE(t.ms, 0.0);
    }
    const std::vector<PassKind> expected =
        m == ShadowMethod::ZFail
            ? std::vector<PassKind>{PassKind::Depth, PassKind::Sides, PassKind::LightCap, PassKind::DarkCap,
                                    PassKind::Lit}
            : std::vector<PassKind>{PassKind::Depth, PassKind::NearCap, PassKind::Sides, PassKind::Lit};
    EXPECT_EQ(kinds, expected) << gl::to_string(m);
  }
}

}  // namespace
}  // namespace nearcap
