// The exact per-pixel reference at the scene's resolution (bunny.json:
// 1920x1080, the 75,408-triangle bunny), on all cores.  Target (issue 2):
// <= 5 s on 2 cores.  Counters split the time between building the grids
// (setup: light facing of every triangle, the two cube-map grids) and tracing
// the pixels, and say how many predicate calls each stage made.
#include <benchmark/benchmark.h>

#include <tbb/global_control.h>

#include <chrono>
#include <cstdlib>
#include <string>

#include "nearcap/exact/light_setup.hpp"
#include "nearcap/exact/pixel_reference.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/scene/scene.hpp"

// The switch between kept and fresh storage, for the interleaved comparison.
#include "../../src/exact/vector_pool.hpp"

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

// The reference's setup alone (building the tracer) on `threads` threads
// (tbb::global_control), at the scene's resolution:
//   cold_ms   nothing cached: the light side and the eye side;
//   warm_ms   the light side from a LightSetupCache (the camera moved 1 cm):
//             the eye side alone, what a camera path pays per frame;
//   light_moved_ms  the eye side from an EyeSetupCache (the light moved 1 cm,
//             the camera still): the light side alone, what a frame whose
//             light moves pays, and each light after the first of a frame.
// Each iteration builds each case twice, interleaved: with the grids'
// storage kept from the builds before (src/exact/vector_pool.hpp, what
// nearcap does), and as *_fresh_ms with every vector freshly allocated, so
// that the two compare in one run on a shared machine.
// The serial fraction of each (Amdahl): f = 2 T2 / T1 - 1 from the runs with
// threads 1 and 2, on an otherwise idle machine:
//   ./analysis/benchmarks/nearcap_benchmarks --benchmark_filter=ReferenceSetup
void BM_ReferenceSetup(benchmark::State& state) {
  const tbb::global_control threads(tbb::global_control::max_allowed_parallelism,
                                    static_cast<std::size_t>(state.range(0)));
  const nearcap::Scene s = nearcap::load_scene(bench_scene());
  nearcap::Scene moved = s;
  nearcap::LightSetupCache cache;
  nearcap::Scene lit = s;
  nearcap::EyeSetupCache eye_cache;
  struct Times {
    double cold = 0, warm = 0, light_moved = 0;
  };
  Times kept, fresh;
  bool step = false;
  auto ms_since = [](std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  };
  for (auto _ : state) {
    for (const bool reuse : {true, false}) {
      nearcap::vector_reuse_enabled() = reuse;
      Times& t = reuse ? kept : fresh;
      auto t0 = std::chrono::steady_clock::now();
      {
        const nearcap::CameraSpaceScene cs(s);
        const nearcap::PixelReferenceTracer tracer(cs, 0);
        benchmark::DoNotOptimize(&tracer);
      }
      t.cold += ms_since(t0);
      moved.camera.view.rows[0][3] = s.camera.view.rows[0][3] + (step ? 0.01 : 0.0);
      step = !step;
      t0 = std::chrono::steady_clock::now();
      {
        const nearcap::CameraSpaceScene cs(moved);
        const nearcap::PixelReferenceTracer tracer(cs, 0, &cache);
        benchmark::DoNotOptimize(&tracer);
      }
      t.warm += ms_since(t0);
      lit.lights[0].position.x = s.lights[0].position.x + (step ? 0.01 : 0.0);
      t0 = std::chrono::steady_clock::now();
      {
        const nearcap::CameraSpaceScene cs(lit);
        const nearcap::PixelReferenceTracer tracer(cs, 0, nullptr, &eye_cache);
        benchmark::DoNotOptimize(&tracer);
      }
      t.light_moved += ms_since(t0);
    }
  }
  nearcap::vector_reuse_enabled() = true;
  const double n = static_cast<double>(state.iterations());
  state.counters["threads"] = static_cast<double>(state.range(0));
  state.counters["cold_ms"] = kept.cold / n;
  state.counters["warm_ms"] = kept.warm / n;
  state.counters["light_moved_ms"] = kept.light_moved / n;
  state.counters["cold_fresh_ms"] = fresh.cold / n;
  state.counters["warm_fresh_ms"] = fresh.warm / n;
  state.counters["light_moved_fresh_ms"] = fresh.light_moved / n;
}
BENCHMARK(BM_ReferenceSetup)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);

}  // namespace
