// nearcap's exact reference against Embree's float32 primary + shadow rays,
// in one process, on the same scene and resolution, both on every core
// (TBB's default arena; Embree builds its BVHs with its own threads).
//
// Each iteration runs, one after the other:
//   embree         the BVHs (vertices to world space, both scenes) and the rays;
//   exact_status   the exact reference with PixelContent::ShadowStatus: what
//                  the ray tracer computes (the surface seen, in shadow or
//                  not), camera-space scene and grids included;
//   exact_full     the whole reference (near-cap count and stencil count);
//   exact_moving   exact_status as a camera path has it: the camera moves
//                  every iteration (two views in turn, 1 cm apart), the light
//                  side comes from a LightSetupCache kept across iterations
//                  (light_setup.hpp), the eye side is built anew;
//   exact_light_moving  exact_status with the light moving every iteration
//                  (1 cm) and the camera still: the eye side comes from an
//                  EyeSetupCache (eye_setup.hpp), the light side is built
//                  anew (what each light after the first of a frame pays).
// Counters: each one's mean milliseconds, its setup and tracing parts, the
// ratios exact / embree (target for exact_status: <= 2 at 1920x1080 with the
// bunny, and on the sweep's 160x120 frames), and the pixels whose shadow
// status the two disagree on (the float ray tracer's wrong pixels).
//   ./analysis/benchmarks/nearcap_raytrace_benchmarks
#include <benchmark/benchmark.h>

#include <chrono>
#include <string>

#include "nearcap/exact/pixel_reference.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/raytrace/shadow_ray_tracer.hpp"

namespace {

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// args: scene index, width, height (0: the scene's own).
const char* const kScenes[] = {"bunny.json", "default.json", "twisted.json"};

void BM_ExactVsEmbree(benchmark::State& state) {
  nearcap::Scene scene = nearcap::load_scene(std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/" +
                                             kScenes[static_cast<std::size_t>(state.range(0))]);
  if (state.range(1) > 0) {
    scene.camera.width = static_cast<int>(state.range(1));
    scene.camera.height = static_cast<int>(state.range(2));
  }
  double embree_build = 0, embree_trace = 0, status_setup = 0, status_trace = 0, full_setup = 0, full_trace = 0;
  double moving_setup = 0, moving_trace = 0;
  std::size_t disagree = 0, seen = 0;
  nearcap::LightSetupCache cache;
  nearcap::Scene moving = scene;  // shares the meshes
  double light_moving_setup = 0, light_moving_trace = 0;
  nearcap::EyeSetupCache eye_cache;
  nearcap::Scene light_moving = scene;
  bool step = false;
  for (auto _ : state) {
    // Each side alone: Embree's device is released before the exact side runs.
    nearcap::raytrace::RaytraceFrame rt;
    {
      const nearcap::raytrace::EmbreeScene embree(scene);
      rt = embree.trace(0);
      embree_build += embree.build_ms();
      embree_trace += rt.trace_ms;
      benchmark::DoNotOptimize(rt.shadowed.data());
    }

    auto t0 = std::chrono::steady_clock::now();
    {
      const nearcap::CameraSpaceScene cs(scene);
      const nearcap::PixelReferenceTracer tracer(cs, 0);
      const double setup = ms_since(t0);
      const nearcap::PixelReference ref = nearcap::compute_pixel_reference(tracer, nearcap::PixelContent::ShadowStatus);
      status_setup += setup;
      status_trace += ref.trace_ms;
      disagree = seen = 0;
      for (std::size_t p = 0; p < ref.stencil.size(); ++p) {
        if (ref.stencil[p] == nearcap::PixelReference::kNothingSeen || ref.object[p] != rt.object[p]) continue;
        ++seen;
        disagree += (ref.stencil[p] > 0) != (rt.shadowed[p] != 0);
      }
    }
    t0 = std::chrono::steady_clock::now();
    {
      const nearcap::CameraSpaceScene cs(scene);
      const nearcap::PixelReferenceTracer tracer(cs, 0);
      const double setup = ms_since(t0);
      const nearcap::PixelReference ref = nearcap::compute_pixel_reference(tracer);
      full_setup += setup;
      full_trace += ref.trace_ms;
      benchmark::DoNotOptimize(ref.stencil.data());
    }
    moving.camera.view.rows[0][3] = scene.camera.view.rows[0][3] + (step ? 0.01 : 0.0);
    step = !step;
    t0 = std::chrono::steady_clock::now();
    {
      const nearcap::CameraSpaceScene cs(moving);
      const nearcap::PixelReferenceTracer tracer(cs, 0, &cache);
      const double setup = ms_since(t0);
      const nearcap::PixelReference ref = nearcap::compute_pixel_reference(tracer, nearcap::PixelContent::ShadowStatus);
      moving_setup += setup;
      moving_trace += ref.trace_ms;
      benchmark::DoNotOptimize(ref.stencil.data());
    }
    light_moving.lights[0].position.x = scene.lights[0].position.x + (step ? 0.01 : 0.0);
    t0 = std::chrono::steady_clock::now();
    {
      const nearcap::CameraSpaceScene cs(light_moving);
      const nearcap::PixelReferenceTracer tracer(cs, 0, nullptr, &eye_cache);
      const double setup = ms_since(t0);
      const nearcap::PixelReference ref = nearcap::compute_pixel_reference(tracer, nearcap::PixelContent::ShadowStatus);
      light_moving_setup += setup;
      light_moving_trace += ref.trace_ms;
      benchmark::DoNotOptimize(ref.stencil.data());
    }
  }
  const double n = static_cast<double>(state.iterations());
  const double embree = (embree_build + embree_trace) / n, status = (status_setup + status_trace) / n,
               full = (full_setup + full_trace) / n;
  state.counters["width"] = scene.camera.width;
  state.counters["height"] = scene.camera.height;
  state.counters["embree_build_ms"] = embree_build / n;
  state.counters["embree_trace_ms"] = embree_trace / n;
  state.counters["embree_ms"] = embree;
  state.counters["exact_status_setup_ms"] = status_setup / n;
  state.counters["exact_status_trace_ms"] = status_trace / n;
  state.counters["exact_status_ms"] = status;
  state.counters["exact_full_ms"] = full;
  state.counters["exact_moving_setup_ms"] = moving_setup / n;
  state.counters["exact_moving_trace_ms"] = moving_trace / n;
  state.counters["exact_moving_ms"] = (moving_setup + moving_trace) / n;
  state.counters["exact_light_moving_setup_ms"] = light_moving_setup / n;
  state.counters["exact_light_moving_ms"] = (light_moving_setup + light_moving_trace) / n;
  state.counters["ratio_status"] = status / embree;
  state.counters["ratio_light_moving"] = (light_moving_setup + light_moving_trace) / n / embree;
  state.counters["ratio_moving"] = (moving_setup + moving_trace) / n / embree;
  state.counters["ratio_full"] = full / embree;
  state.counters["status_disagreements"] = static_cast<double>(disagree);
  state.counters["pixels_compared"] = static_cast<double>(seen);
  state.SetLabel(kScenes[static_cast<std::size_t>(state.range(0))]);
}
BENCHMARK(BM_ExactVsEmbree)
    ->Args({0, 0, 0})
    ->Args({0, 160, 120})
    ->Args({1, 160, 120})
    ->Args({2, 160, 120})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(3.0);

}  // namespace
