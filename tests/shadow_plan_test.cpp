// gl/shadow_plan.hpp: every method has its row for each near-cap kind, and
// the draws a frame records are the ones the header documents for the
// method, occluder by occluder, with Z-fail's where an occluder switches
// (no light frustum, case D).  The expectations are written out here, apart
// from the table the renderer walks, so that a wrong row fails.
#include "nearcap/gl/shadow_plan.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <tuple>
#include <vector>

#include "nearcap/gl/shadow_methods.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/render/pass_kinds.hpp"

namespace nearcap {
namespace {

using gl::GeometryPart;
using gl::LightProjection;
using gl::PassKind;
using gl::ShadowMethod;
using gl::VertexProgram;

Scene small_scene(const std::string& name) {
  Scene s = load_scene(std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/" + name + ".json");
  s.camera.width = 64;
  s.camera.height = 48;
  return s;
}

// How a draw state counts (the plan's VolumeCount), read from its stencil
// operations and clamps.
enum class Count { ZPass, ZPassClamped, ZFail, PreloadAlways, Other };
Count count_of(const gl::DrawState& s) {
  using gl::StencilOp;
  if (s.front.depth_fail == StencilOp::Keep && s.front.depth_pass == StencilOp::IncrementWrap)
    return s.depth_clamp_near && s.depth_clamp_far ? Count::ZPassClamped : Count::ZPass;
  if (s.front.depth_fail == StencilOp::DecrementWrap && s.front.depth_pass == StencilOp::Keep) return Count::ZFail;
  if (s.front.depth_fail == StencilOp::DecrementWrap && s.front.depth_pass == StencilOp::DecrementWrap)
    return Count::PreloadAlways;
  return Count::Other;
}

using Draw = std::tuple<PassKind, GeometryPart, VertexProgram, Count>;

// "sides:part1:program2:count0", for readable failures.
std::vector<std::string> described(const std::vector<Draw>& draws) {
  std::vector<std::string> out;
  for (const auto& [kind, part, program, count] : draws)
    out.push_back(std::string(gl::to_string(kind)) + ":part" + std::to_string(static_cast<int>(part)) + ":program" +
                  std::to_string(static_cast<int>(program)) + ":count" + std::to_string(static_cast<int>(count)));
  return out;
}

// One occluder's volume draws built by a vertex program, as
// shadow_methods.hpp describes each method.
std::vector<Draw> documented_draws(ShadowMethod m, LightProjection p) {
  const Draw zpass_sides{PassKind::Sides, GeometryPart::Sides, VertexProgram::Extrusion, Count::ZPass};
  auto closed = [](Count c) {
    return std::vector<Draw>{{PassKind::Sides, GeometryPart::Sides, VertexProgram::Extrusion, c},
                             {PassKind::LightCap, GeometryPart::LightCap, VertexProgram::Extrusion, c},
                             {PassKind::DarkCap, GeometryPart::DarkCap, VertexProgram::Extrusion, c}};
  };
  switch (m) {
    case ShadowMethod::ZPass:
    case ShadowMethod::ZPPlus:
      return {zpass_sides};
    case ShadowMethod::ZFail:
      return closed(Count::ZFail);
    case ShadowMethod::ZPPlusCorrected:
      if (p == LightProjection::ClippedSides) return {zpass_sides};
      return {{PassKind::Sides, GeometryPart::Sides, VertexProgram::Figure7, Count::ZPass},
              {PassKind::Sides, GeometryPart::Corrective, VertexProgram::Figure7, Count::ZPass}};
    case ShadowMethod::Preload: {
      std::vector<Draw> out = closed(Count::PreloadAlways);
      for (const Draw& d : closed(Count::ZPass)) out.push_back(d);
      return out;
    }
    case ShadowMethod::AtomicZP:
      return {{PassKind::Sides, GeometryPart::Sides, VertexProgram::Extrusion, Count::ZPassClamped}};
  }
  return {};
}

TEST(ShadowPlan, EveryMethodHasItsRowForEachNearCapKind) {
  for (const ShadowMethod m : gl::kAllShadowMethods)
    for (const LightProjection p : {LightProjection::Paper, LightProjection::Composed, LightProjection::ClippedSides}) {
      SCOPED_TRACE(std::string(to_string(m)) + " " + std::string(to_string(p)));
      const gl::ShadowPlan& plan = gl::shadow_plan(m, p);
      EXPECT_EQ(plan.method, m);
      EXPECT_EQ(plan.cap_pass == gl::CapPass::NearCap, gl::uses_near_cap(m));
      if (plan.cap_pass == gl::CapPass::NearCap) {
        EXPECT_EQ(plan.near_cap, gl::near_cap_kind(p));
      }
      EXPECT_EQ(plan.cap_pass == gl::CapPass::EyeCount, m == ShadowMethod::AtomicZP);
      // Only ZP+'s light-frustum cap needs the finite projection, and only
      // it can switch (it has a light frustum to lack).
      const bool light_frustum_cap = gl::uses_near_cap(m) && p != LightProjection::ClippedSides;
      EXPECT_EQ(plan.far_plane == gl::FarPlane::FiniteNeeded, light_frustum_cap);
      EXPECT_EQ(plan.zfail_switch != gl::ZFailSwitch::Never, light_frustum_cap);
      ASSERT_GE(plan.draw_count, 1u);
      ASSERT_LE(plan.draw_count, plan.draws.size());
    }
}

TEST(ShadowPlan, RecordedDrawsAreTheDocumentedOnes) {
  std::size_t frames = 0, switched = 0, fallbacks = 0, near_caps = 0;
  for (const std::string name : {"eye_in_shadow", "case_d", "light_on_near_plane"}) {
    const Scene scene = small_scene(name);
    for (const LightProjection p : {LightProjection::Paper, LightProjection::ClippedSides}) {
      gl::EmulationSettings settings;
      settings.record_draws = true;
      settings.light_frustum.projection = p;
      gl::ShadowFrameBatch batch(scene, 0, settings);
      for (const ShadowMethod m : gl::kAllShadowMethods) {
        SCOPED_TRACE(name + " " + std::string(to_string(p)) + " " + std::string(to_string(m)));
        const gl::ShadowFrame f = batch.render(m);
        ++frames;
        std::vector<Draw> expected;
        for (std::size_t o = 0; o < scene.objects.size(); ++o) {
          if (!scene.objects[o].occluder) continue;
          const bool to_zfail = (gl::uses_near_cap(m) && !f.fallback.empty()) ||
                                std::find(f.zfail_objects.begin(), f.zfail_objects.end(), o) != f.zfail_objects.end();
          switched += to_zfail && gl::uses_near_cap(m) && f.fallback.empty();
          for (const Draw& d : documented_draws(to_zfail ? ShadowMethod::ZFail : m, p)) expected.push_back(d);
        }
        fallbacks += gl::uses_near_cap(m) && !f.fallback.empty();
        std::vector<Draw> drawn;
        std::size_t near_cap_draws = 0;
        for (const gl::DrawCall& d : f.draws) {
          near_cap_draws += d.pass == gl::DrawPass::NearCap;
          if (d.pass != gl::DrawPass::Volume) continue;
          ASSERT_TRUE(d.vertex_stage.has_value());  // no ZF+ far-plane cap with these settings
          drawn.emplace_back(render::draw_kind(d), d.vertex_stage->part, d.vertex_stage->program, count_of(d.state));
        }
        EXPECT_EQ(described(drawn), described(expected));
        if (!gl::uses_near_cap(m) || !f.fallback.empty()) {
          EXPECT_EQ(near_cap_draws, 0u);
        }
        near_caps += near_cap_draws > 0;
        EXPECT_EQ(f.eye_count.has_value(), m == ShadowMethod::AtomicZP);
      }
    }
  }
  // The scenes reach the switches and the near-cap pass.
  EXPECT_EQ(frames, 36u);
  EXPECT_GT(switched, 0u);
  EXPECT_GT(fallbacks, 0u);
  EXPECT_GT(near_caps, 0u);
}

// ZF+ (ZFailFar::FarCap): the far-plane cap follows each closed volume the
// far plane clips, as a dark-cap draw built on the CPU.
TEST(ShadowPlan, FarCapClosesTheZFailVolume) {
  std::size_t cpu_built = 0;
  for (const std::string name : {"default", "room", "twisted", "far_grazing"}) {
    SCOPED_TRACE(name);
    const Scene scene = load_scene(std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/" + name + ".json");
    gl::EmulationSettings settings;
    settings.record_draws = true;
    settings.zfail_far = gl::ZFailFar::FarCap;
    const gl::ShadowFrame f = gl::render_shadow_frame(scene, 0, ShadowMethod::ZFail, settings);
    for (std::size_t k = 0; k < f.draws.size(); ++k) {
      const gl::DrawCall& d = f.draws[k];
      if (d.pass != gl::DrawPass::Volume || d.vertex_stage) continue;
      ++cpu_built;
      EXPECT_EQ(render::draw_kind(d), PassKind::DarkCap);
      ASSERT_GE(k, 3u);
      ASSERT_TRUE(f.draws[k - 1].vertex_stage.has_value());
      EXPECT_EQ(f.draws[k - 1].vertex_stage->part, GeometryPart::DarkCap);
      EXPECT_TRUE(d.state.vertices_on_far_plane);
    }
  }
  EXPECT_GT(cpu_built, 0u);
}

}  // namespace
}  // namespace nearcap
