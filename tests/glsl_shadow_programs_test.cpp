// The shadow passes' GLSL vertex programs (render/glsl_shadow_programs.hpp)
// on Mesa's llvmpipe: each vertex they compute, captured by transform
// feedback, is bit for bit the emulation's float32 result, so that a frame
// whose volumes the GL builds itself is the frame the emulation predicts.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "llvmpipe_fixture.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/render/gl_frame_replay.hpp"
#include "nearcap/render/glsl_shadow_programs.hpp"
#include "nearcap/render/lit_frame.hpp"

namespace nearcap {
namespace {

class GlslShadowProgramsTest : public test::LlvmpipeTest {};

Scene bundled(const std::string& name) { return load_scene(std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/" + name); }

bool same_bits(const gl::Vec4f& a, const gl::Vec4f& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Every program, both arithmetics, both depth mappings, on scenes that take
// every branch of Figure 7 (case_d and light_on_near_plane: near-cap
// counterparts; eye_in_shadow: the corrective quads).  With separately
// rounded products every vertex is the emulation's, bit for bit.  GLSL's
// fma() is not fused on llvmpipe (Mesa lowers it to a multiply and an add,
// each rounded): there the GL's vertices are the separate arithmetic's, on
// every vertex, and differ from the fused emulation's on many; a GPU with
// fused multiply-add is what Arithmetic::Fused models.
TEST_F(GlslShadowProgramsTest, EveryVertexIsTheEmulationsBitForBit) {
  render::ShadowPrograms programs("#version 450 core\nout vec4 colour;\nvoid main() { colour = vec4(1.0); }\n",
                                  "the test's programs");
  std::size_t vertices = 0, differ = 0, counterparts = 0, figure7 = 0, near_cap = 0;
  std::size_t fused_vertices = 0, fused_differ = 0, fused_not_separate = 0;
  for (const char* name : {"default.json", "near_split.json", "case_d.json", "eye_in_shadow.json",
                           "light_on_near_plane.json", "twisted.json", "far_grazing.json"}) {
    const Scene scene = bundled(name);
    for (gl::Arithmetic a : {gl::Arithmetic::Separate, gl::Arithmetic::Fused})
      for (gl::DepthMapping mapping : {gl::DepthMapping::Standard, gl::DepthMapping::Reversed})
        for (gl::ShadowMethod m : gl::kAllShadowMethods) {
          gl::EmulationSettings settings;
          settings.record_draws = true;
          settings.arithmetic = a;
          settings.depth_mapping = mapping;
          if (mapping == gl::DepthMapping::Reversed) settings.depth = gl::DepthFormat::Float32;
          const gl::ShadowFrame frame = gl::render_shadow_frame(scene, 0, m, settings);
          for (const gl::DrawCall& d : frame.draws) {
            if (!d.vertex_stage) continue;
            SCOPED_TRACE(std::string(name) + ", " + std::string(gl::to_string(m)) + ", " +
                         std::string(gl::to_string(d.vertex_stage->program)) +
                         (a == gl::Arithmetic::Fused ? ", fused" : ", separate") + ", " +
                         std::string(gl::to_string(mapping)));
            ASSERT_EQ(d.vertex_stage->inputs.size(), d.clip_vertices.size());
            const std::vector<gl::Vec4f> gpu = programs.capture(d);
            ASSERT_EQ(gpu.size(), d.clip_vertices.size());
            gl::ShadowUniforms separate = d.vertex_stage->uniforms;
            separate.arithmetic = gl::Arithmetic::Separate;
            for (std::size_t k = 0; k < gpu.size(); ++k) {
              const gl::Vec4f expected =
                  gl::run_vertex_program(d.vertex_stage->program, separate, d.vertex_stage->inputs[k]);
              if (a == gl::Arithmetic::Fused) {
                ++fused_vertices;
                fused_differ += !same_bits(gpu[k], d.clip_vertices[k]);
              } else {
                ++vertices;
                EXPECT_TRUE(same_bits(expected, d.clip_vertices[k]));  // the recording is the program's
              }
              if (!same_bits(gpu[k], expected) && ++(a == gl::Arithmetic::Fused ? fused_not_separate : differ) <= 5)
                ADD_FAILURE() << "vertex " << k << ": GL (" << gpu[k].x << ", " << gpu[k].y << ", " << gpu[k].z << ", "
                              << gpu[k].w << "), emulation (" << expected.x << ", " << expected.y << ", " << expected.z
                              << ", " << expected.w << ")";
            }
            if (a == gl::Arithmetic::Fused) continue;
            if (d.vertex_stage->program == gl::VertexProgram::NearCap) ++near_cap;
            if (d.vertex_stage->program != gl::VertexProgram::Figure7) continue;
            ++figure7;
            // A counterpart: a movable vertex that left the extrusion program's result.
            for (std::size_t k = 0; k < gpu.size(); ++k) {
              const gl::ShadowVertex& v = d.vertex_stage->inputs[k];
              counterparts += (v.w == 1.0f || v.w == 0.0f) &&
                              !same_bits(gpu[k], gl::extrusion_program(d.vertex_stage->uniforms, v));
            }
          }
        }
  }
  std::printf(
      "[ glsl     ] separate: %zu vertices, %zu differ (%zu Figure 7 draws, %zu near-cap counterparts; "
      "%zu near-cap draws); fused: %zu vertices, %zu differ from the fused emulation, %zu from the "
      "separate one\n",
      vertices, differ, figure7, counterparts, near_cap, fused_vertices, fused_differ, fused_not_separate);
  EXPECT_EQ(differ, 0u);
  EXPECT_EQ(fused_not_separate, 0u);
  EXPECT_GT(fused_differ, 0u) << "llvmpipe now fuses fma(): Arithmetic::Fused models it; tighten this test";
  EXPECT_GT(figure7, 0u);
  EXPECT_GT(counterparts, 0u) << "no vertex took Figure 7's near-cap branch: the test proves less than it says";
  EXPECT_GT(near_cap, 0u);
}

// So the real GL's stencil, object ids and near-cap pass are the same
// whether it builds the volumes itself or receives the emulation's vertices.
TEST_F(GlslShadowProgramsTest, AFrameBuiltByTheGlIsTheRecordedFrame) {
  std::size_t drawn = 0;
  for (const char* name : {"default.json", "near_split.json", "eye_in_shadow.json", "case_d.json", "room.json"}) {
    const Scene scene = bundled(name);
    for (gl::ShadowMethod m : gl::kAllShadowMethods) {
      SCOPED_TRACE(std::string(name) + ", " + std::string(gl::to_string(m)));
      gl::EmulationSettings settings;
      settings.record_draws = true;
      const gl::ShadowFrame frame = gl::render_shadow_frame(scene, 0, m, settings);
      render::GlFrameReplay replay(frame.width, frame.height, settings.depth);
      const render::ReplayedFrame recorded = replay.replay(frame.draws, 0, render::VertexStage::Recorded);
      const render::ReplayedFrame built = replay.replay(frame.draws, 0, render::VertexStage::Glsl);
      EXPECT_EQ(built.stencil, recorded.stencil);
      EXPECT_EQ(built.object, recorded.object);
      EXPECT_EQ(built.near_cap, recorded.near_cap);
      for (std::uint8_t s : built.stencil) drawn += s != 0;
    }
  }
  EXPECT_GT(drawn, 0u);
}

// The lit frame (the renderer's default builds its volumes in GLSL): the
// same picture and stencils as from the recorded vertices.
TEST_F(GlslShadowProgramsTest, TheLitFrameIsTheSameEitherWay) {
  for (const char* name : {"near_split.json", "eye_in_shadow.json"})
    for (gl::ShadowMethod m : {gl::ShadowMethod::ZPass, gl::ShadowMethod::ZFail, gl::ShadowMethod::ZPPlusCorrected}) {
      SCOPED_TRACE(std::string(name) + ", " + std::string(gl::to_string(m)));
      const Scene scene = bundled(name);
      gl::EmulationSettings settings;
      settings.record_draws = true;
      std::vector<gl::ShadowFrame> frames;
      for (std::size_t k = 0; k < scene.lights.size(); ++k)
        frames.push_back(gl::render_shadow_frame(scene, k, m, settings));
      render::LitFrameOptions recorded, built;
      recorded.vertex_stage = render::VertexStage::Recorded;
      recorded.read_stencils = built.read_stencils = true;
      EXPECT_EQ(built.vertex_stage, render::VertexStage::Glsl);
      const render::LitFrame a = render::render_lit_frame(scene, frames, settings.depth, recorded);
      const render::LitFrame b = render::render_lit_frame(scene, frames, settings.depth, built);
      EXPECT_EQ(a.rgb, b.rgb);
      EXPECT_EQ(a.stencils, b.stencils);
    }
}

// `render --compare --vertex-stage glsl|recorded`: the same counts either
// way, the stage named in the record; an unknown stage is a usage error.
TEST(RenderCommand, TheVertexStageIsAChoiceWithTheSameCounts) {
  nlohmann::json counts[2];
  int k = 0;
  for (const char* stage : {"glsl", "recorded"}) {
    const test::CliResult r = test::run_cli(std::string("render data/scenes/case_d.json --light 0 --compare --method "
                                                        "zpass,zpplus-corrected,policy --vertex-stage ") +
                                                stage,
                                            "render");
    if (r.exit_code == 2 && r.err.find("error (gl)") != std::string::npos)
      GTEST_SKIP() << "no headless OpenGL here: " << r.err;
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j.at("vertex_stage"), stage);
    for (const nlohmann::json& m : j.at("methods"))
      counts[k].push_back({m.at("method"), m.at("gl_vs_emulation"), m.at("gl_vs_exact"), m.at("cracks")});
    ++k;
  }
  EXPECT_EQ(counts[0], counts[1]);
  EXPECT_EQ(counts[0].size(), 3u);
  const test::CliResult bad =
      test::run_cli("render data/scenes/case_d.json --light 0 --compare --vertex-stage gpu", "render");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--vertex-stage"), std::string::npos) << bad.err;
}

TEST(VertexStage, NamesRoundTrip) {
  for (render::VertexStage s : {render::VertexStage::Recorded, render::VertexStage::Glsl})
    EXPECT_EQ(render::vertex_stage_from_string(render::to_string(s)), s);
  EXPECT_FALSE(render::vertex_stage_from_string("gpu"));
  EXPECT_NE(render::glsl_vertex_shader(gl::VertexProgram::Figure7, gl::Arithmetic::Fused).find("#define FUSED 1"),
            std::string::npos);
}

}  // namespace
}  // namespace nearcap
