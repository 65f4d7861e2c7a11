// A frame batch's shared draws (src/gl/shared_draws.hpp): the methods of a
// batch draw each (geometry, program, uniforms) once and set it up once per
// clipping and culling state; every frame must still be, bit for bit and
// counter for counter, the frame rendered alone.  And the two stages of a
// draw (Framebuffer::set_up, rasterize) are the draw.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstring>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "../src/gl/shared_draws.hpp"
#include "nearcap/gl/pipeline.hpp"
#include "nearcap/gl/shadow_methods.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/scene/scene.hpp"

namespace nearcap {
namespace {

using gl::ShadowMethod;

void expect_same_counters(const gl::DrawCounters& a, const gl::DrawCounters& b, const std::string& what) {
  EXPECT_EQ(a.triangles, b.triangles) << what;
  EXPECT_EQ(a.clipped, b.clipped) << what;
  EXPECT_EQ(a.culled, b.culled) << what;
  EXPECT_EQ(a.rasterized, b.rasterized) << what;
  EXPECT_EQ(a.in_view, b.in_view) << what;
  EXPECT_EQ(a.fragments, b.fragments) << what;
  EXPECT_EQ(a.bounds_culled, b.bounds_culled) << what;
  EXPECT_EQ(a.depth_passed, b.depth_passed) << what;
}

bool same_bits(const std::vector<gl::Vec4f>& a, const std::vector<gl::Vec4f>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(gl::Vec4f)) == 0);
}

// Settings under which methods share different draws: Z-fail's and
// preload's caps (infinite far plane), the near-cap pass of both ZP+
// methods, the Z-pass sides with and without AtomicZP's depth clamp; ZF+'s
// far cap (it reads the shared vertices back), the clipped-sides cap, the
// reversed depth mapping, volume culling (a state the setup does not read).
std::vector<std::pair<std::string, gl::EmulationSettings>> settings_cases() {
  std::vector<std::pair<std::string, gl::EmulationSettings>> out;
  gl::EmulationSettings s;
  s.record_draws = true;
  out.emplace_back("default", s);
  gl::EmulationSettings far_cap = s;
  far_cap.zfail_far = gl::ZFailFar::FarCap;
  out.emplace_back("zfail far cap", far_cap);
  gl::EmulationSettings infinite = s;
  infinite.zpass_far = gl::ZPassFar::Infinite;
  out.emplace_back("zpass infinite", infinite);
  gl::EmulationSettings clipped = s;
  clipped.light_frustum.projection = gl::LightProjection::ClippedSides;
  out.emplace_back("clipped-sides cap", clipped);
  gl::EmulationSettings reversed = s;
  reversed.depth_mapping = gl::DepthMapping::Reversed;
  reversed.depth = gl::DepthFormat::Float32;
  out.emplace_back("reversed", reversed);
  gl::EmulationSettings culled = s;
  culled.volume_culling = gl::VolumeCulling::Both;
  out.emplace_back("volume culling", culled);
  gl::EmulationSettings mesa = s;
  mesa.raster.mesa_clipper = true;
  mesa.raster.viewport = gl::ViewportArithmetic::Llvmpipe;
  mesa.zfail_far = gl::ZFailFar::DepthClampFar;
  out.emplace_back("mesa clipper, one-sided clamp", mesa);
  return out;
}

TEST(SharedDraws, EveryFrameOfABatchIsTheFrameRenderedAlone) {
  // Z-fail and preload first, so that later methods find their caps and
  // sides; AtomicZP last (its clamped sides share the vertices, not the setup).
  const std::vector<ShadowMethod> order{ShadowMethod::ZFail,  ShadowMethod::Preload,         ShadowMethod::ZPass,
                                        ShadowMethod::ZPPlus, ShadowMethod::ZPPlusCorrected, ShadowMethod::AtomicZP};
  std::size_t reused_triangles = 0;  // volume and cap triangles a later method found set up (counted as drawn)
  for (const char* name : {"eye_in_shadow.json", "near_cap_bunny_wall.json", "case_d.json"}) {
    const Scene scene = load_scene(std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/" + name);
    for (const auto& [label, settings] : settings_cases()) {
      gl::ShadowFrameBatch batch(scene, 0, settings);
      for (ShadowMethod m : order) {
        const std::string what = std::string(name) + ", " + label + ", " + std::string(to_string(m));
        const gl::ShadowFrame shared = batch.render(m), alone = gl::render_shadow_frame(scene, 0, m, settings);
        EXPECT_EQ(shared.stencil, alone.stencil) << what;
        EXPECT_EQ(shared.object, alone.object) << what;
        EXPECT_EQ(shared.near_cap, alone.near_cap) << what;
        EXPECT_EQ(shared.fallback, alone.fallback) << what;
        expect_same_counters(shared.depth_pass, alone.depth_pass, what + " depth");
        expect_same_counters(shared.cap_pass, alone.cap_pass, what + " cap");
        expect_same_counters(shared.volume_pass, alone.volume_pass, what + " volume");
        ASSERT_EQ(shared.draws.size(), alone.draws.size()) << what;
        for (std::size_t d = 0; d < shared.draws.size(); ++d)
          EXPECT_TRUE(same_bits(shared.draws[d].clip_vertices, alone.draws[d].clip_vertices)) << what << " draw " << d;
        if (m != order.front()) reused_triangles += shared.volume_pass.triangles + shared.cap_pass.triangles;
      }
    }
  }
  std::printf("volume and cap triangles drawn by later methods of a batch: %zu\n", reused_triangles);
}

// A vertex program's run is found again by the uniforms it reads and only
// by those: a uniform it does not read (the light's matrices for the
// extrusion program, say, which ZP+'s frames set and Z-pass's do not) finds
// the run of the other frame, whose bits are those the program computes
// from either; one it reads runs it again.
TEST(SharedDraws, AProgramRunIsFoundByTheUniformsItReads) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> entry(-3.0f, 3.0f);
  auto matrix = [&] {
    gl::Mat4f m;
    for (float& e : m.m) e = entry(rng);
    return m;
  };
  std::vector<gl::ShadowVertex> inputs;
  for (int k = 0; k < 600; ++k)
    inputs.push_back({entry(rng), entry(rng), entry(rng), std::array{0.f, 1.f, 2.f, 4.f}[k % 4]});
  gl::ShadowUniforms base;
  base.modelview_projection = matrix();
  base.light_modelview = matrix();
  base.light_projection = matrix();
  base.light_position = {entry(rng), entry(rng), entry(rng), 1.0f};
  struct Field {
    const char* name;
    std::function<void(gl::ShadowUniforms&)> change;
    std::vector<gl::VertexProgram> read_by;
  };
  using P = gl::VertexProgram;
  const std::vector<Field> fields{
      {"modelview_projection",
       [&](gl::ShadowUniforms& u) { u.modelview_projection = matrix(); },
       {P::Extrusion, P::Figure7}},
      {"light_modelview", [&](gl::ShadowUniforms& u) { u.light_modelview = matrix(); }, {P::Figure7, P::NearCap}},
      {"light_projection", [&](gl::ShadowUniforms& u) { u.light_projection = matrix(); }, {P::Figure7, P::NearCap}},
      {"light_position", [&](gl::ShadowUniforms& u) { u.light_position.y += 0.5f; }, {P::Extrusion, P::Figure7}},
      {"arithmetic",
       [](gl::ShadowUniforms& u) { u.arithmetic = gl::Arithmetic::Fused; },
       {P::Extrusion, P::Figure7, P::NearCap}},
      {"depth_mapping", [](gl::ShadowUniforms& u) { u.depth_mapping = gl::DepthMapping::Reversed; }, {P::Figure7}},
  };
  for (P program : {P::Extrusion, P::Figure7, P::NearCap})
    for (const Field& field : fields) {
      const std::string what = std::string(to_string(program)) + ", " + field.name;
      gl::ShadowUniforms other = base;
      field.change(other);
      const bool read = std::find(field.read_by.begin(), field.read_by.end(), program) != field.read_by.end();
      gl::SharedDraws draws;
      const std::vector<gl::Vec4f>& first = draws.run(inputs, program, base).clip;
      const gl::SharedDraws::Program again = draws.run(inputs, program, other);
      EXPECT_EQ(&again.clip != &first, read) << what;
      EXPECT_TRUE(same_bits(again.clip, gl::run_vertex_program(program, other, inputs))) << what;
      if (read) {
        EXPECT_FALSE(same_bits(again.clip, first)) << what << ": the change is not seen in the bits";
      }
    }
}

// A full-viewport quad at clip depth z (w = 1), counter-clockwise, with a
// triangle across the near plane (clipped) and one behind the eye.
std::vector<gl::Vec4f> quads_and_clipped() {
  return {{-1, -1, 0.5f, 1}, {1, -1, 0.5f, 1}, {1, 1, 0.5f, 1}, {-1, -1, 0.5f, 1}, {1, 1, 0.5f, 1}, {-1, 1, 0.5f, 1},
          {-1, -1, -2, 1},   {1, -1, 0.2f, 1}, {0, 1, 0.2f, 1}, {0, 0, 2, -1},     {1, 0, 2, -1},   {0, 1, 2, -1}};
}

TEST(SharedDraws, ASetUpRasterizedWithAnotherStateIsThatStatesDraw) {
  gl::DrawState count;  // depth test, +1 on pass front, -1 back
  count.front.depth_pass = gl::StencilOp::IncrementWrap;
  count.back.depth_pass = gl::StencilOp::DecrementWrap;
  gl::DrawState other = count;  // the same setup, other fragment operations
  other.depth_func = gl::DepthFunc::Always;
  other.front.depth_pass = gl::StencilOp::DecrementWrap;
  other.scissor = gl::PixelRect{1, 1, 6, 5};
  ASSERT_TRUE(gl::same_setup(count, other));
  gl::DrawState clamped = count;
  clamped.depth_clamp_near = true;
  EXPECT_FALSE(gl::same_setup(count, clamped));
  gl::DrawState culling = count;
  culling.cull = gl::CullFace::Back;
  EXPECT_FALSE(gl::same_setup(count, culling));

  const std::vector<gl::Vec4f> clip = quads_and_clipped();
  gl::Framebuffer drawn(8, 6, gl::DepthFormat::Fixed24), staged(8, 6, gl::DepthFormat::Fixed24);
  gl::SetUpTriangles set_up;
  staged.set_up(clip, count, {}, set_up);
  EXPECT_EQ(set_up.counters.triangles, 4u);
  EXPECT_EQ(set_up.counters.clipped, 1u);  // behind the eye
  for (const gl::DrawState& s : {count, other, count}) {
    const gl::DrawCounters a = drawn.draw(clip, s, {});
    gl::DrawCounters b = set_up.counters;
    b += staged.rasterize(set_up, s, {});
    expect_same_counters(a, b, "");
    EXPECT_EQ(drawn.stencil(), staged.stencil());
    EXPECT_EQ(drawn.depth(), staged.depth());
  }
}

// The fragments a rasterization kept, replayed with any state of the same
// setup, are that state's draw: random triangles (both facings, some
// crossing the near plane) on framebuffers of both depth formats and both
// depth interpolations, drawn with depth writes, then counted with every
// depth function, scissor, depth bounds and stencil operations, and with
// depth writes, under which the fragments that pass depend on each pixel
// seeing its fragments in submission order.
TEST(SharedDraws, ReplayedFragmentsAreTheStatesDraw) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> coordinate(-1.3f, 1.3f), depth(-1.2f, 1.0f);
  std::vector<gl::Vec4f> clip;
  for (int t = 0; t < 3 * 120; ++t) clip.push_back({coordinate(rng), coordinate(rng), depth(rng), 1.0f});
  gl::DrawState writes;  // the depth pre-pass
  writes.depth_write = true;
  writes.object_id = 3;
  std::vector<gl::DrawState> states;
  for (gl::DepthFunc f : {gl::DepthFunc::Less, gl::DepthFunc::Greater, gl::DepthFunc::Always}) {
    gl::DrawState s;
    s.depth_func = f;
    s.front.depth_pass = gl::StencilOp::IncrementWrap;
    s.back.depth_pass = gl::StencilOp::DecrementWrap;
    s.back.depth_fail = gl::StencilOp::IncrementWrap;
    states.push_back(s);
    s.scissor = gl::PixelRect{3, 2, 17, 11};
    states.push_back(s);
    s.depth_bounds = std::array<double, 2>{0.3, 0.8};
    std::swap(s.front, s.back);
    states.push_back(s);
    // Depth writes: how many fragments pass depends on their order.
    s.depth_write = true;
    s.object_id = 5;
    states.push_back(s);
  }
  for (gl::DepthFormat format : {gl::DepthFormat::Fixed24, gl::DepthFormat::Float32})
    for (gl::DepthInterpolation interpolation : {gl::DepthInterpolation::Exact, gl::DepthInterpolation::Llvmpipe}) {
      gl::RasterSettings raster;
      raster.depth = interpolation;
      const std::string what = std::string(format == gl::DepthFormat::Fixed24 ? "fixed24" : "float32") +
                               (interpolation == gl::DepthInterpolation::Llvmpipe ? ", llvmpipe depth" : "");
      // 70 rows: three bands, the last one partial.
      gl::Framebuffer drawn(23, 70, format), replayed(23, 70, format);
      gl::SetUpTriangles set_up;
      replayed.set_up(clip, writes, raster, set_up);
      gl::CoveredFragments kept;
      expect_same_counters(
          drawn.draw(clip, writes, raster),
          [&] {
            gl::DrawCounters c = set_up.counters;
            c += replayed.rasterize(set_up, writes, raster, &kept);
            return c;
          }(),
          what + ", kept");
      ASSERT_EQ(kept.bands.size(), 3u);
      std::size_t fronts = 0;
      for (const auto& band : kept.bands)
        for (const gl::CoveredFragments::Covered& f : band) fronts += (f.pixel_and_facing & kept.kFront) != 0;
      EXPECT_GT(fronts, 0u) << what;
      EXPECT_LT(fronts, kept.size()) << what;
      for (std::size_t k = 0; k < states.size(); ++k) {
        gl::DrawCounters a = drawn.draw(clip, states[k], raster);
        gl::DrawCounters b = set_up.counters;
        b += replayed.replay(kept, states[k], raster);
        expect_same_counters(a, b, what + ", state " + std::to_string(k));
        EXPECT_EQ(drawn.stencil(), replayed.stencil()) << what << ", state " << k;
      }
      EXPECT_EQ(drawn.depth(), replayed.depth()) << what;
      EXPECT_EQ(drawn.objects(), replayed.objects()) << what;
    }
}

// A batch keeps a setup's fragments and replays them where they fit in what
// its kept fragments leave of SharedDraws::kKeptFragments; a draw that does
// not fit, alone or beside those kept, is rasterized each time, and a later
// one that fits is still kept.
TEST(SharedDraws, FragmentsAreKeptWithinTheBound) {
  // One full-viewport quad covers more than the bound.
  const int height = 1024, width = static_cast<int>(gl::SharedDraws::kKeptFragments / height) + 1;
  ASSERT_GT(static_cast<std::size_t>(width) * height, gl::SharedDraws::kKeptFragments);
  const std::vector<gl::ShadowVertex> large{{-1, -1, 0.5f, 1}, {1, -1, 0.5f, 1}, {1, 1, 0.5f, 1},
                                            {-1, -1, 0.5f, 1}, {1, 1, 0.5f, 1},  {-1, 1, 0.5f, 1}};
  const std::vector<gl::ShadowVertex> small{{-0.1f, -0.1f, 0.5f, 1}, {0.1f, -0.1f, 0.5f, 1}, {0.1f, 0.1f, 0.5f, 1}};
  gl::ShadowUniforms u;  // the identity: the inputs are clip space
  for (int k = 0; k < 4; ++k) u.modelview_projection.at(k, k) = 1.0f;
  gl::DrawState count;
  count.depth_func = gl::DepthFunc::Always;
  count.front.depth_pass = gl::StencilOp::IncrementWrap;
  gl::Framebuffer fb(width, height, gl::DepthFormat::Fixed24), alone(width, height, gl::DepthFormat::Fixed24);
  gl::SharedDraws draws;
  auto rasterize = [&](const std::vector<gl::ShadowVertex>& inputs) {
    const gl::SharedDraws::SetUp set_up = draws.set_up(inputs, gl::VertexProgram::Extrusion, u, fb, count, {});
    const gl::SharedDraws::Fragments f = draws.rasterize(set_up, fb, count, {});
    alone.draw(gl::run_vertex_program(gl::VertexProgram::Extrusion, u, inputs), count, {});
    EXPECT_EQ(fb.stencil(), alone.stencil());
    return f.replayed;
  };
  EXPECT_FALSE(rasterize(small));
  EXPECT_TRUE(rasterize(small));  // kept
  EXPECT_FALSE(rasterize(large));
  EXPECT_FALSE(rasterize(large));  // over the bound: rasterized again
  EXPECT_TRUE(rasterize(small));   // kept before
  std::vector<gl::ShadowVertex> later = small;
  for (gl::ShadowVertex& v : later) v.x += 0.2f;
  EXPECT_FALSE(rasterize(later));
  EXPECT_TRUE(rasterize(later));  // it fits

  // Two draws over 60% of the viewport each: the first is kept, the second
  // does not fit beside it.
  draws = gl::SharedDraws();
  auto part = [&](float left, float right) {
    return std::vector<gl::ShadowVertex>{{left, -1, 0.5f, 1}, {right, -1, 0.5f, 1}, {right, 1, 0.5f, 1},
                                         {left, -1, 0.5f, 1}, {right, 1, 0.5f, 1},  {left, 1, 0.5f, 1}};
  };
  const std::vector<gl::ShadowVertex> first = part(-1.0f, 0.2f), second = part(-0.2f, 1.0f);
  EXPECT_FALSE(rasterize(first));
  EXPECT_FALSE(rasterize(second));
  EXPECT_TRUE(rasterize(first));
  EXPECT_FALSE(rasterize(second));
}

// Framebuffer::rasterize keeps a draw's fragments where they are at most
// keep_at_most: a quad over two of the framebuffer's bands of rows, kept
// with a bound of its fragments, not with one less.
TEST(SharedDraws, ADrawIsKeptWhereItsFragmentsFit) {
  const std::vector<gl::Vec4f> quad{{-0.5f, -0.5f, 0, 1}, {0.5f, -0.5f, 0, 1}, {0.5f, 0.5f, 0, 1},
                                    {-0.5f, -0.5f, 0, 1}, {0.5f, 0.5f, 0, 1},  {-0.5f, 0.5f, 0, 1}};
  gl::Framebuffer fb(12, 70, gl::DepthFormat::Fixed24);
  gl::DrawState state;
  state.depth_func = gl::DepthFunc::Always;
  gl::SetUpTriangles set_up;
  fb.set_up(quad, state, {}, set_up);
  gl::CoveredFragments kept;
  const std::uint64_t fragments = fb.rasterize(set_up, state, {}, &kept).fragments;
  EXPECT_EQ(fragments, 6u * 35u);
  ASSERT_EQ(kept.bands.size(), 3u);
  EXPECT_FALSE(kept.bands[0].empty());
  EXPECT_FALSE(kept.bands[1].empty());
  EXPECT_EQ(kept.size(), fragments);
  fb.rasterize(set_up, state, {}, &kept, fragments);
  EXPECT_EQ(kept.size(), fragments);
  fb.rasterize(set_up, state, {}, &kept, fragments - 1);
  EXPECT_TRUE(kept.bands.empty());
}

}  // namespace
}  // namespace nearcap
