// One frame of each float method through the software GL pipeline, on the
// 52,000-triangle armadillo at 1280x720 (data/scenes/armadillo.json; another
// scene with NEARCAP_BENCH_METHODS_SCENE).  Target (issue 3): a frame through
// every method well under a second on 2 cores.  Counters say what dominates:
// fragments of the depth pre-pass, the near-cap pass and the volume passes,
// and each pass's share of the time.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <string>

#include "nearcap/gl/shadow_methods.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/scene/scene.hpp"

namespace {

const nearcap::Scene& scene() {
  static const nearcap::Scene s = [] {
    const char* env = std::getenv("NEARCAP_BENCH_METHODS_SCENE");
    return nearcap::load_scene(env ? env : std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/armadillo.json");
  }();
  return s;
}

void BM_ShadowMethod(benchmark::State& state) {
  const auto method = nearcap::gl::kAllShadowMethods[static_cast<std::size_t>(state.range(0))];
  state.SetLabel(std::string(to_string(method)));
  nearcap::gl::PassTimes sum;
  nearcap::gl::ShadowFrame frame;
  for (auto _ : state) {
    frame = nearcap::gl::render_shadow_frame(scene(), 0, method);
    sum.setup_ms += frame.times.setup_ms;
    sum.depth_ms += frame.times.depth_ms;
    sum.cap_ms += frame.times.cap_ms;
    sum.volume_ms += frame.times.volume_ms;
    benchmark::DoNotOptimize(frame.stencil.data());
  }
  const double total = sum.total();
  state.counters["setup_share"] = sum.setup_ms / total;
  state.counters["depth_share"] = sum.depth_ms / total;
  state.counters["cap_share"] = sum.cap_ms / total;
  state.counters["volume_share"] = sum.volume_ms / total;
  state.counters["volume_fragments"] = static_cast<double>(frame.volume_pass.fragments);
  state.counters["cap_fragments"] = static_cast<double>(frame.cap_pass.fragments);
  state.counters["depth_fragments"] = static_cast<double>(frame.depth_pass.fragments);
}

// All five methods back to back: the figure the target speaks of.
void BM_AllShadowMethods(benchmark::State& state) {
  for (auto _ : state)
    for (auto m : nearcap::gl::kAllShadowMethods) {
      const auto frame = nearcap::gl::render_shadow_frame(scene(), 0, m);
      benchmark::DoNotOptimize(frame.stencil.data());
    }
}

}  // namespace

BENCHMARK(BM_ShadowMethod)->DenseRange(0, 4)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_AllShadowMethods)->Unit(benchmark::kMillisecond);
