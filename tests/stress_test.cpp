// Stress: a few thousand hard configurations of the hard-case sampler
// (analysis/hard_case_sampler.hpp: the light 2^-k from the near plane or in
// it, grazing light, eye in shadow, scenes far from the origin, tiny near
// planes, occluders straddling the near plane, several occluders or lights,
// real meshes) through the exact kernel, checking its internal identities on
// every pixel (cap against the direct segment count, the Z-pass identity) and
// the near-cap arrangement against the pixel counts, then through the float
// pipeline.  The seed is fixed (kDefaultStressSeed), so that a failure in CI's
// log replays as it is, and printed; NEARCAP_STRESS_SEED=<seed> runs another
// (and `nearcap sample --seed S --index K --width 8 --height 8` writes
// configuration K alone), NEARCAP_STRESS_COUNT=<n> changes its length
// (default 2000).
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <map>

#include "nearcap/analysis/hard_case_sampler.hpp"
#include "nearcap/error.hpp"
#include "nearcap/exact/near_cap.hpp"
#include "nearcap/gl/shadow_methods.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/judge/crack_distances.hpp"
#include "nearcap/judge/crack_map.hpp"
#include "support/sampled_scenes.hpp"
#include "zpass_identity.hpp"

namespace nearcap {
namespace {

std::uint64_t env_or(const char* name, std::uint64_t fallback) {
  const char* v = std::getenv(name);
  return v ? std::strtoull(v, nullptr, 10) : fallback;
}

// The default run's seed: any fixed value; other seeds explore further.
constexpr std::uint64_t kDefaultStressSeed = 2026;

// The run's seed (NEARCAP_STRESS_SEED, or kDefaultStressSeed), printed for replay.
std::uint64_t announced_seed() {
  const std::uint64_t seed = env_or("NEARCAP_STRESS_SEED", kDefaultStressSeed);
  std::printf("stress seed %llu (replay: NEARCAP_STRESS_SEED=%llu)\n", static_cast<unsigned long long>(seed),
              static_cast<unsigned long long>(seed));
  return seed;
}

// The hard-case sampler (analysis/hard_case_sampler.hpp, every kind, the
// bunny left out for time) at 8 x 8 pixels: configuration k of the run's seed.
analysis::HardCaseSampler stress_sampler(std::uint64_t seed) {
  analysis::SamplerSpec spec = test::bundled_sampler_spec(seed);
  spec.width = 8;
  spec.height = 8;
  return analysis::HardCaseSampler(spec);
}

TEST(Stress, ExactKernelIdentitiesOnHardConfigurations) {
  const std::uint64_t seed = announced_seed();
  const std::uint64_t count = env_or("NEARCAP_STRESS_COUNT", 2000);
  const analysis::HardCaseSampler sampler = stress_sampler(seed);
  std::map<std::string, int> ran, degenerate_light;
  int identity_pixels = 0;
  const test::SampleWalk walk =
      test::for_each_sampled_scene(sampler, count, [&](const Scene& scene, const analysis::HardCase& sample) {
        const std::uint64_t k = sample.index;
        const std::string kind(analysis::to_string(sample.kind));
        const std::string& json = sample.scene_json;
        ++ran[kind];
        const test::IdentityReport r = test::check_zpass_identity(scene);
        ASSERT_TRUE(r.holds) << "configuration " << k << " (" << kind << "), seed " << seed << ": " << r.failure << "\n"
                             << json;
        identity_pixels += r.checked;
        // The near-cap arrangement agrees with the per-pixel counts where a pixel
        // centre lies inside a face.
        const CameraSpaceScene cs(scene);
        try {
          const NearCap cap = NearCap::build(cs, 0);
          const PixelReferenceTracer tracer(cs, 0);
          for (int j = 0; j < scene.camera.height; ++j)
            for (int i = 0; i < scene.camera.width; ++i) {
              const SamplePoint p = pixel_centre(scene.camera.frustum, scene.camera.width, scene.camera.height, i, j);
              if (const auto c = cap.count_at(p.exact.x, p.exact.y)) {
                ASSERT_EQ(*c, tracer.trace(i, j, nullptr).cap)
                    << "configuration " << k << ", seed " << seed << ", pixel " << i << " " << j << "\n"
                    << json;
              }
            }
        } catch (const Error& e) {
          ASSERT_EQ(e.kind(), ErrorKind::Degenerate) << e.what();
          ++degenerate_light[kind];
        }
      });
  for (const auto& [kind, n] : ran) std::printf("  %-24s %d configurations\n", kind.c_str(), n);
  // Samples the scene reader rejects (e.g. the light inside a box), by error kind.
  for (const auto& [kind, n] : walk.rejected) std::printf("  rejected (%s): %zu\n", kind.c_str(), n);
  for (const auto& [kind, n] : degenerate_light) std::printf("  light in the near plane (%s): %d\n", kind.c_str(), n);
  std::printf("  %d pixels checked against the Z-pass identity\n", identity_pixels);
  EXPECT_GT(ran["light-near-plane"], 0);
  EXPECT_GT(ran["light-in-near-plane"], 0);
  EXPECT_GT(ran["grazing"], 0);
  EXPECT_GT(identity_pixels, 0);
}

// The same hard configurations through the float pipeline: every method runs
// without an internal check failing (snapped coordinates in range, clipping
// at extreme light frusta), preload's stencil equals Z-fail's bit for bit,
// and the ZP+ methods fall back to Z-fail exactly when the float light
// frustum is undefined.  Wrong pixels per method are printed (a measurement:
// float against exact on configurations built to be hard).
TEST(Stress, FloatPipelineOnHardConfigurations) {
  const std::uint64_t seed = announced_seed();
  const std::uint64_t count = env_or("NEARCAP_STRESS_COUNT", 2000);
  const analysis::HardCaseSampler sampler = stress_sampler(seed);
  std::map<std::string, std::size_t> wrong, cracks, fallbacks, refused;
  std::size_t pixels = 0, switches = 0, switched_wrong = 0, switched_wrong_clamp_far = 0;
  const test::SampleWalk walk =
      test::for_each_sampled_scene(sampler, count, [&](const Scene& scene, const analysis::HardCase& sample) {
        const std::uint64_t k = sample.index;
        const std::string& json = sample.scene_json;
        const CameraSpaceScene cs(scene);
        const PixelReferenceTracer tracer(cs, 0);
        const PixelReference ref = compute_pixel_reference(tracer);
        CrackDistances distances(tracer, ref);
        for (std::uint32_t seen : ref.stencil) pixels += seen != PixelReference::kNothingSeen;
        const gl::ShadowFrame zfail = gl::render_shadow_frame(scene, 0, gl::ShadowMethod::ZFail);
        for (gl::ShadowMethod m : gl::kAllShadowMethods) {
          const std::string name(to_string(m));
          gl::ShadowFrame f;
          try {
            f = m == gl::ShadowMethod::ZFail ? zfail : gl::render_shadow_frame(scene, 0, m);
          } catch (const Error& e) {
            // Float32 transforms so degenerate that a vertex is (0, 0, 0, 0) after
            // clipping: the emulation refuses the frame (a GL would draw NaNs).
            // Only the light frustum of the near-cap methods gets there.
            ASSERT_EQ(e.kind(), ErrorKind::Range) << e.what();
            ASSERT_TRUE(gl::uses_near_cap(m))
                << name << ", configuration " << k << ", seed " << seed << ": " << e.what();
            ++refused[name];
            continue;
          }
          CrackReport report = judge_frame(f, ref);
          distances.measure(report);
          wrong[name] += report.wrong;
          cracks[name] += *report.cracks;
          ASSERT_LE(*report.cracks, report.wrong);
          if (m == gl::ShadowMethod::Preload) {
            ASSERT_EQ(f.stencil, zfail.stencil) << "configuration " << k << ", seed " << seed << "\n" << json;
          }
          if (gl::uses_near_cap(m)) {
            ASSERT_EQ(f.fallback.empty(), f.light_frustum.defined) << "configuration " << k << ", seed " << seed;
            fallbacks[name] += !f.fallback.empty();
          }
          if (m == gl::ShadowMethod::ZPPlusCorrected && !f.zfail_objects.empty()) {
            ++switches;
            switched_wrong += judge_frame(f, ref).wrong;
            // The same switch with far-only depth clamp (the README's finding:
            // GL_DEPTH_CLAMP also disables near clipping).
            gl::EmulationSettings far_only;
            far_only.switch_clamp = gl::SwitchClamp::DepthClampFar;
            switched_wrong_clamp_far += judge_frame(gl::render_shadow_frame(scene, 0, m, far_only), ref).wrong;
          }
        }
      });
  const std::size_t scenes = walk.scenes;
  std::printf("  %zu configurations, %zu pixels seen\n", scenes, pixels);
  for (const auto& [name, n] : wrong)
    std::printf("  %-17s %zu wrong pixels (%zu cracks), %zu fallbacks to zfail, %zu frames refused\n", name.c_str(), n,
                cracks[name], fallbacks[name], refused[name]);
  std::printf(
      "  zpplus-corrected switched to zfail (case D) in %zu configurations: %zu wrong pixels there "
      "with GL_DEPTH_CLAMP, %zu with far-only clamp\n",
      switches, switched_wrong, switched_wrong_clamp_far);
  EXPECT_GT(scenes, 0u);
  // Far-only clamping never makes the case-D switch worse than GL_DEPTH_CLAMP.
  EXPECT_LE(switched_wrong_clamp_far, switched_wrong);
}

}  // namespace
}  // namespace nearcap
