// The exact per-pixel reference at the scene's resolution (bunny.json:
// 1920x1080, the 75,408-triangle bunny), on all cores.  Target (issue 2):
// <= 5 s on 2 cores.  Counters split the time between building the grids
// (setup: light facing of every triangle, the two cube-map grids) and tracing
// the pixels, and say how many predicate calls each stage made.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <string>

#include "nearcap/exact/pixel_reference.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/scene/scene.hpp"

namespace {

std::string bench_scene() {
  if (const char* env = std::getenv("NEARCAP_BENCH_SCENE")) return env;
  return std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/bunny.json";
}

void BM_PixelReference(benchmark::State& state) {
  const nearcap::Scene s = nearcap::load_scene(bench_scene());
  const nearcap::CameraSpaceScene cs(s);
  double setup = 0, trace = 0;
  std::uint64_t ray = 0, shadow = 0, cap = 0, exact = 0;
  for (auto _ : state) {
    const nearcap::PixelReference ref = nearcap::compute_pixel_reference(cs, 0);
    setup += ref.setup_ms;
    trace += ref.trace_ms;
    using nearcap::Predicate;
    ray = ref.stats.filtered[static_cast<int>(Predicate::RayHit)];
    shadow = ref.stats.filtered[static_cast<int>(Predicate::ShadowCrossing)];
    cap = ref.stats.filtered[static_cast<int>(Predicate::SegmentCrossing)];
    exact = ref.stats.total_exact();
    benchmark::DoNotOptimize(ref.stencil.data());
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["width"] = s.camera.width;
  state.counters["height"] = s.camera.height;
  state.counters["setup_ms"] = setup / n;
  state.counters["trace_ms"] = trace / n;
  state.counters["ray_hit_calls"] = static_cast<double>(ray);
  state.counters["cap_calls"] = static_cast<double>(cap);
  state.counters["shadow_calls"] = static_cast<double>(shadow);
  state.counters["exact_calls"] = static_cast<double>(exact);
}
BENCHMARK(BM_PixelReference)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);

}  // namespace
