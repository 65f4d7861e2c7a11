// Exact classification (certified filter + rationals when needed) against the
// same classification in plain float32, on the largest bundled mesh.
//
// Both sides do the whole per-frame job for one light and one occluder: move
// the vertices to camera space, decide the facing of every triangle, collect
// the silhouette edges and classify each edge's side quad against the near
// plane.  Target (issue 2): exact <= 2x float.  Read the ratio off one run of
// both benchmarks (same process, same machine state).
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <memory>
#include <string>

#include "nearcap/exact/classification.hpp"
#include "nearcap/gl/engine_classification.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/scene/scene.hpp"

namespace {

std::string bench_scene() {
  if (const char* env = std::getenv("NEARCAP_BENCH_SCENE")) return env;
  return std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/bunny.json";
}

const nearcap::Scene& scene() {
  static const nearcap::Scene s = nearcap::load_scene(bench_scene());
  return s;
}

std::size_t largest_occluder(const nearcap::Scene& s) {
  std::size_t best = 0, best_n = 0;
  for (std::size_t o = 0; o < s.objects.size(); ++o)
    if (s.objects[o].occluder && s.objects[o].mesh->triangle_count() > best_n) {
      best = o;
      best_n = s.objects[o].mesh->triangle_count();
    }
  return best;
}

void BM_ClassificationFloat(benchmark::State& state) {
  const nearcap::Scene& s = scene();
  const std::size_t o = largest_occluder(s);
  std::size_t edges = 0;
  for (auto _ : state) {
    const nearcap::EngineSilhouette e = nearcap::engine_silhouette(s, o, 0);
    edges = e.edges.size();
    benchmark::DoNotOptimize(e.cases.data());
  }
  state.counters["triangles"] = static_cast<double>(s.objects[o].mesh->triangle_count());
  state.counters["silhouette_edges"] = static_cast<double>(edges);
}

void BM_ClassificationExact(benchmark::State& state) {
  const nearcap::Scene& s = scene();
  const std::size_t o = largest_occluder(s);
  std::size_t edges = 0, exact_calls = 0;
  for (auto _ : state) {
    nearcap::FilterStats stats;
    const nearcap::CameraSpaceScene cs(s);
    const nearcap::ObjectClassification c = nearcap::classify_object_exact(cs, o, 0, &stats);
    edges = c.edges.size();
    exact_calls = stats.total_exact();
    benchmark::DoNotOptimize(c.edges.data());
  }
  state.counters["silhouette_edges"] = static_cast<double>(edges);
  state.counters["exact_fallbacks"] = static_cast<double>(exact_calls);
}

}  // namespace

BENCHMARK(BM_ClassificationFloat)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ClassificationExact)->Unit(benchmark::kMillisecond);
