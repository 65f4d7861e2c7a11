// The switch policy's cost against issue 12's targets, measured frame by frame
// in one process: where Z-pass is right (every occluder's exact near-cap
// empty) the policy's frame against Z-pass's (target: within 5 %), elsewhere
// against ZP+ corrected's (no more).  The sweep measures each method's frame
// in its own batch among many others, so its times carry the order and the
// allocation of each batch; here both frames of a pair are drawn alternately
// (the policy first on every other pair), each from a fresh batch, the
// policy's decision included, and summed over the pairs.
//
// Configurations: the first 600 of the hard-case sampler, seed 7 (the
// sweep's held-out set; NEARCAP_BENCH_POLICY_SAMPLES for another count,
// NEARCAP_BENCH_POLICY_SEED for another seed), 48x36
// (NEARCAP_BENCH_POLICY_SIZE=WxH for another size), and every frame of the
// seven bundled paths at their own size; the shipped policy
// (data/policy.json; NEARCAP_BENCH_POLICY for another).  Counters: policy_over_base (the ratio), pairs, and the
// fragments' ratio.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "nearcap/analysis/camera_path.hpp"
#include "nearcap/analysis/hard_case_sampler.hpp"
#include "nearcap/analysis/switch_policy.hpp"
#include "nearcap/error.hpp"
#include "nearcap/exact/camera_space.hpp"
#include "nearcap/exact/pixel_reference.hpp"
#include "nearcap/gl/shadow_methods.hpp"
#include "nearcap/io/scene_file.hpp"

namespace {

using Clock = std::chrono::steady_clock;
// What a frame loop times: the choice, its prices left out
// (switch_policy.hpp, DecisionPricing).
constexpr auto kChoice = nearcap::analysis::DecisionPricing::ChoiceOnly;

struct Pair {
  std::shared_ptr<const nearcap::Scene> scene;
  std::shared_ptr<const nearcap::CameraSpaceScene> cs;
  std::size_t light = 0;
  bool zpass_right = false;
};

struct Setup {
  nearcap::analysis::SwitchPolicy policy;
  std::vector<Pair> pairs;
};

void add_pairs(const std::string& json, const std::string& name, Setup& out) {
  std::shared_ptr<nearcap::Scene> scene;
  try {
    scene = std::make_shared<nearcap::Scene>(nearcap::parse_scene(json, name, "."));
  } catch (const nearcap::Error&) {
    return;  // the sampler's bad input: a light inside an occluder
  }
  auto cs = std::make_shared<nearcap::CameraSpaceScene>(*scene);
  for (std::size_t light = 0; light < scene->lights.size(); ++light) {
    try {
      const nearcap::PixelReference ref = nearcap::compute_pixel_reference(*cs, light);
      bool right = true;
      for (std::size_t o = 0; o < scene->objects.size(); ++o)
        right = right && !(scene->objects[o].occluder && ref.cap_pixels_by_object[o] > 0);
      // Frames the float pipeline refuses are left out, as the sweep's report leaves them.
      nearcap::gl::ShadowFrameBatch(*scene, light).render(nearcap::gl::ShadowMethod::ZPass);
      out.pairs.push_back({scene, cs, light, right});
    } catch (const nearcap::Error&) {
    }
  }
}

nearcap::analysis::SwitchPolicy shipped_policy() {
  const char* policy = std::getenv("NEARCAP_BENCH_POLICY");
  return nearcap::analysis::load_policy(policy ? policy : std::string(NEARCAP_SOURCE_DIR) + "/data/policy.json");
}

const Setup& sampler_setup() {
  static const Setup s = [] {
    Setup out;
    out.policy = shipped_policy();
    const char* count = std::getenv("NEARCAP_BENCH_POLICY_SAMPLES");
    const std::uint64_t samples = count ? std::strtoull(count, nullptr, 10) : 600;
    nearcap::analysis::SamplerSpec spec;
    const char* seed = std::getenv("NEARCAP_BENCH_POLICY_SEED");
    spec.seed = seed ? std::strtoull(seed, nullptr, 10) : 7;
    if (const char* size = std::getenv("NEARCAP_BENCH_POLICY_SIZE"))
      if (std::sscanf(size, "%dx%d", &spec.width, &spec.height) != 2) spec.width = 48, spec.height = 36;
    spec.mesh_directory = std::string(NEARCAP_SOURCE_DIR) + "/data/meshes";
    const nearcap::analysis::HardCaseSampler sampler(spec);
    for (std::uint64_t k = 0; k < samples; ++k)
      add_pairs(sampler.sample(k).scene_json, "sample " + std::to_string(k), out);
    return out;
  }();
  return s;
}

const Setup& paths_setup() {
  static const Setup s = [] {
    Setup out;
    out.policy = shipped_policy();
    for (const char* name :
         {"bunny_orbit", "eye_in_shadow", "fly_around", "looking_at", "looking_away", "near_plane_sweep", "zoom"}) {
      const nearcap::analysis::CameraPath path =
          nearcap::analysis::load_camera_path(std::string(NEARCAP_SOURCE_DIR) + "/data/paths/" + name + ".json");
      for (int frame = 0; frame < path.frames; ++frame)
        add_pairs(nearcap::analysis::path_frame_json(path, frame),
                  std::string(name) + " frame " + std::to_string(frame), out);
    }
    return out;
  }();
  return s;
}

// range(0): 1 where Z-pass is right (against Z-pass), 0 elsewhere (against
// ZP+ corrected); range(1): 1 with the near-cap pass's light-pyramid filter
// (gl/light_pyramid_cull.hpp, the default), 0 without it; range(2): 0 the
// hard-case sampler, 1 every frame of the seven bundled camera paths.
void BM_PolicyCost(benchmark::State& state) {
  const bool right = state.range(0) == 1;
  const bool cull = state.range(1) == 1;
  const bool paths = state.range(2) == 1;
  const auto base_method = right ? nearcap::gl::ShadowMethod::ZPass : nearcap::gl::ShadowMethod::ZPPlusCorrected;
  state.SetLabel(std::string(right ? "where Z-pass is right, against zpass" : "elsewhere, against zpplus-corrected") +
                 (cull ? "" : "; no light-pyramid filter") + (paths ? "; bundled paths" : "; hard cases"));
  const Setup& s = paths ? paths_setup() : sampler_setup();
  double policy_ms = 0, base_ms = 0, policy_fragments = 0, base_fragments = 0;
  std::size_t pairs = 0;
  for (auto _ : state) {
    std::size_t k = 0;
    for (const Pair& p : s.pairs) {
      if (p.zpass_right != right) continue;
      auto draw_base = [&] {
        const auto t0 = Clock::now();
        nearcap::gl::ShadowFrameBatch batch(*p.scene, p.light);
        const nearcap::gl::ShadowFrame f = batch.render(base_method);
        base_ms += std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
        base_fragments += static_cast<double>(f.volume_pass.fragments + f.cap_pass.fragments);
        benchmark::DoNotOptimize(f.stencil.data());
      };
      auto draw_policy = [&] {
        const auto t0 = Clock::now();
        nearcap::analysis::PolicyDecision d = nearcap::analysis::decide(s.policy, *p.cs, p.light, {}, nullptr, kChoice);
        d.settings.cull_light_pyramid = cull;
        nearcap::gl::ShadowFrameBatch batch(*p.scene, p.light, d.settings);
        const nearcap::gl::ShadowFrame f = batch.render(d.object_methods);
        policy_ms += std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
        policy_fragments += static_cast<double>(f.volume_pass.fragments + f.cap_pass.fragments);
        benchmark::DoNotOptimize(f.stencil.data());
      };
      if (k++ % 2 == 0) {
        draw_base();
        draw_policy();
      } else {
        draw_policy();
        draw_base();
      }
    }
    pairs = k;
  }
  state.counters["pairs"] = static_cast<double>(pairs);
  state.counters["policy_over_base"] = base_ms > 0 ? policy_ms / base_ms : 0;
  state.counters["fragments_over_base"] = base_fragments > 0 ? policy_fragments / base_fragments : 0;
}

// What `nearcap evaluate` draws between two decisions (the exact reference
// and a dozen rules' frames) leaves little of a decision's code and data in
// the caches; writing this much other memory does the same.
constexpr std::size_t kEvictionBytes = std::size_t{64} << 20;

void evict_caches(std::vector<std::uint64_t>& other) {
  for (std::size_t i = 0; i < other.size(); i += 8) other[i] += i;
  benchmark::ClobberMemory();
}

// The decision alone (analysis::decide with the shipped policy's device
// profile, its choice: DecisionPricing::ChoiceOnly), every (configuration, light) of the set in turn, each decided
// range(1) times in a row: 1 is the order `nearcap evaluate` times its first
// call in (a different frame before each), 2 also times the call repeated
// at once (warm, as a renderer's frame loop pays it), 0 decides once after
// writing 64 MB of other memory (cold, as `nearcap evaluate`'s first call),
// 3 decides the set's previous (configuration, light) untimed after writing
// it and then this one (the code warm, this one's data cold).
// range(0): 0 the hard-case sampler, 1 the bundled paths.  Counter:
// us_per_decision.
void BM_PolicyDecision(benchmark::State& state) {
  const bool paths = state.range(0) == 1;
  const int repeat = static_cast<int>(state.range(1));
  state.SetLabel(std::string(paths ? "bundled paths" : "hard cases") +
                 (repeat == 2   ? ", each decided twice"
                  : repeat == 3 ? ", caches evicted, then the previous one decided before each"
                  : repeat == 0 ? ", caches evicted before each"
                                : ""));
  const Setup& s = paths ? paths_setup() : sampler_setup();
  std::vector<std::uint64_t> other(kEvictionBytes / sizeof(std::uint64_t), 1);
  std::size_t decisions = 0;
  double ms = 0;
  for (auto _ : state)
    for (std::size_t i = 0; i < s.pairs.size(); ++i)
      for (int k = 0; k < (repeat == 2 ? 2 : 1); ++k) {
        const Pair& p = s.pairs[i];
        if (repeat == 0 || repeat == 3) evict_caches(other);
        if (repeat == 3) {
          const Pair& before = s.pairs[(i + s.pairs.size() - 1) % s.pairs.size()];
          const nearcap::analysis::PolicyDecision warm_up =
              nearcap::analysis::decide(s.policy, *before.cs, before.light, {}, nullptr, kChoice);
          benchmark::DoNotOptimize(warm_up.object_methods.data());
        }
        const auto t0 = Clock::now();
        const nearcap::analysis::PolicyDecision d =
            nearcap::analysis::decide(s.policy, *p.cs, p.light, {}, nullptr, kChoice);
        ms += std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
        benchmark::DoNotOptimize(d.object_methods.data());
        ++decisions;
      }
  state.counters["us_per_decision"] = decisions > 0 ? 1e3 * ms / static_cast<double>(decisions) : 0;
}

// What a renderer builds before each decision: the exact camera-space scene
// (CameraSpaceScene) of every (configuration, light) in turn, as `nearcap
// evaluate` and `nearcap render` build it per frame; range(1) 1 also decides
// on it (the decision's whole per-frame cost, as those commands count it).
// range(0): 0 the hard-case sampler, 1 the bundled paths.  Counter:
// us_per_scene.
void BM_CameraSpaceScene(benchmark::State& state) {
  const bool paths = state.range(0) == 1;
  const bool decide = state.range(1) == 1;
  state.SetLabel(std::string(paths ? "bundled paths" : "hard cases") + (decide ? ", and the decision" : ""));
  const Setup& s = paths ? paths_setup() : sampler_setup();
  std::size_t scenes = 0;
  double ms = 0;
  for (auto _ : state)
    for (const Pair& p : s.pairs) {
      const auto t0 = Clock::now();
      const nearcap::CameraSpaceScene cs(*p.scene);
      if (decide) {
        const nearcap::analysis::PolicyDecision d =
            nearcap::analysis::decide(s.policy, cs, p.light, {}, nullptr, kChoice);
        benchmark::DoNotOptimize(d.object_methods.data());
      }
      ms += std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
      benchmark::DoNotOptimize(cs.max_abs(0));
      ++scenes;
    }
  state.counters["us_per_scene"] = scenes > 0 ? 1e3 * ms / static_cast<double>(scenes) : 0;
}

}  // namespace

BENCHMARK(BM_CameraSpaceScene)->ArgsProduct({{0, 1}, {0, 1}})->Unit(benchmark::kMicrosecond)->MinTime(1.0);
BENCHMARK(BM_PolicyDecision)->ArgsProduct({{0, 1}, {0, 1, 2, 3}})->Unit(benchmark::kMicrosecond)->MinTime(1.0);
BENCHMARK(BM_PolicyCost)->ArgsProduct({{1, 0}, {1, 0}, {0, 1}})->Unit(benchmark::kMillisecond)->MinTime(3.0);
