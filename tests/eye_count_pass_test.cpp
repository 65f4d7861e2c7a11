// AtomicZP's eye count on llvmpipe (render/eye_count_pass.hpp): the GLSL
// pass's count equals the emulation's float32 count (gl/eye_count.hpp) on
// every bundled scene and where that float count is wrong, and it reaches the
// stencil on the GPU.
#include <gtest/gtest.h>

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "box_scene.hpp"
#include "cli_support.hpp"
#include "llvmpipe_fixture.hpp"
#include "nearcap/gl/eye_count.hpp"
#include "nearcap/gl/shadow_methods.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/render/eye_count_pass.hpp"
#include "nearcap/render/gl_frame_replay.hpp"
#include "nearcap/render/lit_frame.hpp"

namespace nearcap {
namespace {

class EyeCountPassTest : public test::LlvmpipeTest {};

std::vector<std::size_t> occluders(const Scene& scene) {
  std::vector<std::size_t> out;
  for (std::size_t o = 0; o < scene.objects.size(); ++o)
    if (scene.objects[o].occluder) out.push_back(o);
  return out;
}

std::vector<std::filesystem::path> bundled_scenes() {
  std::vector<std::filesystem::path> out;
  for (const auto& e : std::filesystem::directory_iterator(std::string(NEARCAP_SOURCE_DIR) + "/data/scenes"))
    if (e.path().extension() == ".json") out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

TEST_F(EyeCountPassTest, CountEqualsTheEmulationsOnEveryBundledScene) {
  render::EyeCountPass pass;
  std::size_t scenes = 0, nonzero = 0;
  for (const auto& path : bundled_scenes()) {
    const Scene scene = load_scene(path.string());
    ++scenes;
    for (std::size_t light = 0; light < scene.lights.size(); ++light) {
      const gl::FloatEyeCount emulated = gl::float_eye_count(scene, light);
      const render::EyeCountReadBack real =
          pass.run_and_read_back(render::eye_count_inputs(scene, light, occluders(scene), gl::Arithmetic::Separate));
      EXPECT_EQ(real.count, emulated.count) << path.filename() << " light " << light;
      EXPECT_EQ(real.triangles, emulated.triangles) << path.filename();
      std::printf("%-32s light %zu: eye count %zu over %zu triangles (pass %.3f ms, read back %.3f ms)\n",
                  path.filename().string().c_str(), light, real.count, real.triangles, real.pass_ms, real.read_back_ms);
      nonzero += real.count != 0;
    }
  }
  EXPECT_GE(scenes, 17u);
  // eye_in_shadow (1) and atomiczp_side_plane (float 1, exact 0) at least:
  // the comparison is not of zeros alone.
  EXPECT_GE(nonzero, 2u);
}

// Eyes within 3 float32 ulps of a side plane in steps of 1/64 ulp
// (atomiczp_test.cpp's hard case): the float count is wrong on some of them,
// and the GL's count is the emulation's on every one, wrong or right.
TEST_F(EyeCountPassTest, CountEqualsTheEmulationsWhereTheFloatCountIsWrong) {
  render::EyeCountPass pass;
  const double step = std::ldexp(1.0, -30);
  int compared = 0, float_wrong = 0;
  for (int k = -192; k <= 192; ++k) {
    if (k == 0) continue;
    const Scene scene = test::eye_near_side_plane(test::kSidePlaneX + k * step);
    const std::size_t truth = k < 0 ? 1u : 0u;
    const std::size_t emulated = gl::float_eye_count(scene, 0).count;
    const std::size_t real =
        pass.run_and_read_back(render::eye_count_inputs(scene, 0, {0}, gl::Arithmetic::Separate)).count;
    EXPECT_EQ(real, emulated) << "k " << k;
    ++compared;
    float_wrong += emulated != truth;
  }
  std::printf("%d eyes compared, the float count wrong on %d of them\n", compared, float_wrong);
  EXPECT_GT(float_wrong, 0);
}

// Triangles in camera space whose eye -> light line passes within a few
// float32 roundings of an edge (the light on the line from the eye through a
// point of the edge, nudged by 2^-e relative, e in 18..30): the edge's
// triple product's sign is decided by its rounding.  One run per triangle,
// the GL's count (0 or 1) against the emulation's test of the same floats.
// Both programs: GLSL's fma() is not fused on llvmpipe (Mesa lowers it to a
// multiply and an add, glsl_shadow_programs_test.cpp), so there the fused
// program decides as the separate emulation does, and differs from the
// fused one on some triangles; a GPU that fuses is what Arithmetic::Fused
// models.
TEST_F(EyeCountPassTest, EachGrazingTriangleIsDecidedAsTheEmulationDecidesIt) {
  render::EyeCountPass pass;
  std::mt19937 rng(28);
  std::uniform_real_distribution<double> unit(-1, 1), along(0.05, 0.95);
  std::uniform_int_distribution<int> exponent(18, 30);
  std::printf("seed 28\n");
  int crossed = 0, fused_differ = 0, mismatches = 0;
  for (int k = 0; k < 600; ++k) {
    Vec3d v[3];
    for (Vec3d& p : v) p = {unit(rng), unit(rng), -5 + unit(rng)};
    const double s = along(rng);
    const Vec3d on_edge = v[0] + s * (v[1] - v[0]);
    const double nudge_mantissa = unit(rng);  // one draw a statement: the same values under every compiler
    const double nudge = std::ldexp(nudge_mantissa, -exponent(rng));
    const Vec3d l = 2.0 * (on_edge + nudge * Vec3d{unit(rng), unit(rng), unit(rng)});
    // Wound to face the light, as a closed occluder's lit triangles are.
    if (dot(cross(v[1] - v[0], v[2] - v[0]), l - v[0]) < 0) std::swap(v[1], v[2]);
    render::EyeCountInputs in;
    in.light = {static_cast<float>(l.x), static_cast<float>(l.y), static_cast<float>(l.z), 1.0f};
    in.occluders.resize(1);
    in.occluders[0].uniforms.modelview.m = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    in.occluders[0].triangles = 1;
    for (const Vec3d& p : v)
      in.vertices.push_back({static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z), 1.0f});
    const bool separate = gl::float_eye_segment_crosses(in.vertices[0], in.vertices[1], in.vertices[2], in.light, false,
                                                        gl::Arithmetic::Separate);
    const bool fused = gl::float_eye_segment_crosses(in.vertices[0], in.vertices[1], in.vertices[2], in.light, false,
                                                     gl::Arithmetic::Fused);
    crossed += separate;
    fused_differ += separate != fused;
    for (gl::Arithmetic ar : {gl::Arithmetic::Separate, gl::Arithmetic::Fused}) {
      in.arithmetic = ar;
      const std::size_t real = pass.run_and_read_back(in).count;
      EXPECT_EQ(real, separate ? 1u : 0u) << "triangle " << k << (ar == gl::Arithmetic::Fused ? ", fused" : "");
      mismatches += real != (separate ? 1u : 0u);
    }
  }
  std::printf("600 triangles: %d crossed, the fused emulation differs on %d; %d GL counts differ\n", crossed,
              fused_differ, mismatches);
  EXPECT_GT(crossed, 100);
  EXPECT_LT(crossed, 500);
  EXPECT_GT(fused_differ, 0) << "no triangle where fusing decides: the test does not reach the rounding";
}

// One triangle the eye -> light segment crosses (the eye at the origin, the
// light at z = -10, the triangle at z = -5 facing the light), `copies` times.
render::EyeCountInputs crossed_triangles(std::size_t copies) {
  render::EyeCountInputs in;
  in.light = {0, 0, -10, 1};
  in.occluders.resize(1);
  in.occluders[0].uniforms.modelview.m = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  in.occluders[0].triangles = copies;
  for (std::size_t c = 0; c < copies; ++c) {
    in.vertices.push_back({-1, -1, -5, 1});
    in.vertices.push_back({0, 1, -5, 1});
    in.vertices.push_back({1, -1, -5, 1});
  }
  return in;
}

// The stencil of a width x height framebuffer after write_stencil.
std::vector<std::uint8_t> stencil_after_write(render::EyeCountPass& pass, int width, int height) {
  GLuint framebuffer = 0, buffer = 0;
  glGenFramebuffers(1, &framebuffer);
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
  glGenRenderbuffers(1, &buffer);
  glBindRenderbuffer(GL_RENDERBUFFER, buffer);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH24_STENCIL8, width, height);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, buffer);
  EXPECT_EQ(glCheckFramebufferStatus(GL_FRAMEBUFFER), static_cast<GLenum>(GL_FRAMEBUFFER_COMPLETE));
  glViewport(0, 0, width, height);
  glClearStencil(7);
  glClear(GL_STENCIL_BUFFER_BIT);
  pass.write_stencil();
  std::vector<std::uint8_t> stencil(static_cast<std::size_t>(width) * height);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width, height, GL_STENCIL_INDEX, GL_UNSIGNED_BYTE, stencil.data());
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glDeleteRenderbuffers(1, &buffer);
  glDeleteFramebuffers(1, &framebuffer);
  EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
  return stencil;
}

// 300 crossed triangles: the counter holds 300, every stencil pixel 300 mod
// 256 = 44, on the GPU (stencil export) and by the read-back path alike.
TEST_F(EyeCountPassTest, StencilHoldsTheCountModulo256OnTheGpuAndByReadBack) {
  const render::EyeCountInputs in = crossed_triangles(300);
  ASSERT_TRUE(gl::float_eye_segment_crosses(in.vertices[0], in.vertices[1], in.vertices[2], in.light, false));
  render::EyeCountPass pass;
  ASSERT_TRUE(pass.stencil_on_gpu()) << "llvmpipe has GL_ARB_shader_stencil_export";
  for (int path = 0; path < 2; ++path) {
    if (path == 1) pass.use_read_back_stencil();
    pass.run(in);
    const std::vector<std::uint8_t> stencil = stencil_after_write(pass, 37, 23);
    const auto other = std::find_if(stencil.begin(), stencil.end(), [](std::uint8_t s) { return s != 44; });
    EXPECT_TRUE(other == stencil.end()) << (path == 0 ? "on the GPU" : "read back") << ": pixel "
                                        << (other - stencil.begin()) << " holds " << int(*other) << ", not 44";
    EXPECT_EQ(pass.read_count(), 300u);
  }
}

// The lit frame counts on the GPU: its AtomicZP stencil is the replay's
// (cleared to the emulation's count, the same GLSL programs), and the count
// it read back is the emulation's.
TEST_F(EyeCountPassTest, LitFrameStencilStartsAtTheGpuCount) {
  for (const char* name : {"eye_in_shadow.json", "default.json", "atomiczp_side_plane.json"}) {
    const Scene scene = load_scene(std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/" + name);
    gl::EmulationSettings settings;
    settings.record_draws = true;
    const gl::ShadowFrame frame = gl::render_shadow_frame(scene, 0, gl::ShadowMethod::AtomicZP, settings);
    ASSERT_TRUE(frame.eye_count);
    render::LitFrameOptions options;
    options.read_stencils = true;
    const render::LitFrame lit = render::render_lit_frame(scene, {frame}, settings.depth, options);
    ASSERT_EQ(lit.eye_counts.size(), 1u);
    ASSERT_TRUE(lit.eye_counts[0]);
    EXPECT_EQ(*lit.eye_counts[0], *frame.eye_count) << name;
    render::GlFrameReplay replay(frame.width, frame.height, settings.depth);
    const render::ReplayedFrame replayed = replay.replay(frame.draws, 0, render::VertexStage::Glsl);
    std::size_t differ = 0;
    for (std::size_t p = 0; p < replayed.stencil.size(); ++p) differ += replayed.stencil[p] != lit.stencils[0][p];
    std::printf("%s: eye count %zu; lit frame vs replay: %zu stencil pixels differ\n", name, *lit.eye_counts[0],
                differ);
    EXPECT_EQ(differ, 0u) << name;
  }
}

// render --compare: AtomicZP's record carries the GL's count beside the
// emulation's, and the replay cleared to the GL's count matches the emulation.
TEST_F(EyeCountPassTest, RenderCompareReportsTheGlCount) {
  const test::CliResult r =
      test::run_cli("render data/scenes/eye_in_shadow.json --light 0 --method atomiczp --compare", "eye_count_pass");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json root = nlohmann::json::parse(r.out);
  const nlohmann::json& m = root["methods"][0];
  ASSERT_TRUE(m.contains("eye_count")) << r.out;
  EXPECT_EQ(m["eye_count"]["gl"], 1);
  EXPECT_EQ(m["eye_count"]["emulation"], 1);
  EXPECT_EQ(m["eye_count"]["triangles"], 24);
  EXPECT_EQ(m["gl_vs_emulation"], 0);
  EXPECT_EQ(m["gl_vs_exact"], 0);
}

std::size_t differing(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b) {
  std::size_t n = 0;
  for (std::size_t p = 0; p < a.size() && p < b.size(); ++p) n += a[p] != b[p];
  return n + (a.size() > b.size() ? a.size() - b.size() : b.size() - a.size());
}

// A frame that draws one occluder with AtomicZP and the other with a ZP+
// (near_split: the slab and the torus; test::two_boxes: the eye in the
// second box's volume, the first's cut by the near plane), on the GL: the lit frame's stencil
// (the eye-count pass over the AtomicZP occluder, the near-cap and volumes
// over it) equals the replay's (cleared to the emulation's count), the GL's
// count is the emulation's, and the replay differs from the emulation on no
// more pixels than the two single-method frames do together (the sides'
// rasterization on llvmpipe), its near-cap pass no more than ZP+'s own.
TEST_F(EyeCountPassTest, MixedFrameOnTheGlIsTheEmulations) {
  for (const Scene& scene :
       {load_scene(std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/near_split.json"), test::two_boxes(true, true)}) {
    const std::vector<std::size_t> occ = occluders(scene);
    ASSERT_EQ(occ.size(), 2u);
    for (const auto& [zpplus, projection] : {std::pair{gl::ShadowMethod::ZPPlus, gl::LightProjection::ClippedSides},
                                             std::pair{gl::ShadowMethod::ZPPlusCorrected, gl::LightProjection::Paper}})
      for (std::size_t atomic = 0; atomic < 2; ++atomic) {
        gl::EmulationSettings settings;
        settings.record_draws = true;
        settings.light_frustum.projection = projection;
        std::vector<gl::ShadowMethod> methods(scene.objects.size(), gl::ShadowMethod::ZPass);
        methods[occ[atomic]] = gl::ShadowMethod::AtomicZP;
        methods[occ[1 - atomic]] = zpplus;
        const std::string what = scene.source + ": " + std::string(gl::to_string(zpplus)) + " + atomiczp on object " +
                                 std::to_string(occ[atomic]);
        gl::ShadowFrameBatch batch(scene, 0, settings);
        const gl::ShadowFrame frame = batch.render(methods);
        const gl::ShadowFrame all_atomic = batch.render(gl::ShadowMethod::AtomicZP);
        const gl::ShadowFrame all_zpplus = batch.render(zpplus);
        ASSERT_TRUE(frame.eye_count) << what;
        const std::size_t count_alone = gl::float_eye_count(scene, 0, {occ[atomic]}).count;
        EXPECT_EQ(*frame.eye_count, count_alone) << what;

        render::LitFrameOptions options;
        options.read_stencils = true;
        const render::LitFrame lit = render::render_lit_frame(scene, {frame}, settings.depth, options);
        ASSERT_EQ(lit.eye_counts.size(), 1u);
        ASSERT_TRUE(lit.eye_counts[0]) << what;
        EXPECT_EQ(*lit.eye_counts[0], *frame.eye_count) << what;
        render::GlFrameReplay replay(frame.width, frame.height, settings.depth);
        const render::ReplayedFrame mixed = replay.replay(frame.draws, 0, render::VertexStage::Glsl);
        const render::ReplayedFrame a = replay.replay(all_atomic.draws, 0, render::VertexStage::Glsl);
        const render::ReplayedFrame z = replay.replay(all_zpplus.draws, 0, render::VertexStage::Glsl);
        const std::size_t lit_vs_replay = differing(lit.stencils[0], mixed.stencil);
        const std::size_t mixed_differ = differing(mixed.stencil, frame.stencil);
        const std::size_t singles_differ =
            differing(a.stencil, all_atomic.stencil) + differing(z.stencil, all_zpplus.stencil);
        // A frame whose near-cap pass draws nothing (the cap empty, or the
        // occluder switched to Z-fail) is replayed without one: all zero.
        const std::size_t cap_differ =
            differing(mixed.near_cap.empty() ? std::vector<std::uint8_t>(frame.near_cap.size(), 0) : mixed.near_cap,
                      frame.near_cap);
        const std::size_t zpplus_cap_differ = differing(z.near_cap, all_zpplus.near_cap);
        std::printf(
            "%s: eye count %zu; lit vs replay %zu; replay vs emulation %zu (single-method frames %zu); near-cap %zu "
            "(ZP+ alone %zu)\n",
            what.c_str(), *frame.eye_count, lit_vs_replay, mixed_differ, singles_differ, cap_differ, zpplus_cap_differ);
        EXPECT_EQ(lit_vs_replay, 0u) << what;
        EXPECT_LE(mixed_differ, singles_differ) << what;
        EXPECT_FALSE(frame.near_cap.empty()) << what;
        EXPECT_LE(cap_differ, zpplus_cap_differ) << what;
      }
  }
}

}  // namespace
}  // namespace nearcap
