// AtomicZP's near-plane condition (analysis/near_rectangle_pyramid.hpp,
// occluder_clear_of_near_rectangle_pyramid, as the switch policy's candidate
// test runs it) on the two largest bundled meshes, beside the exact eye count
// (light facing included) and the float eye count that the same candidate
// test computes on the same frame.
//
// Frames: the bundled scene as drawn (no triangle across the slab
// -near <= z < 0: the per-vertex filter alone), and the camera moved so that
// the slab cuts the mesh:
//   - beside: the whole mesh in the slab, beside the view (every triangle
//     tested against the pyramid, none meeting it: the largest count);
//   - along: the eye close to the surface, looking along it, the near plane
//     slicing it, no triangle meeting the pyramid (every triangle across the
//     slab tested);
//   - away: the eye close to the surface, looking away from it, the eye's
//     plane cutting it, no triangle meeting the pyramid;
//   - facing: the eye close to the surface, looking at it: a triangle meets
//     the pyramid and the condition refuses at the first one.
// The light is the scene's.  Counters of BM_NearPlaneCondition: triangles
// (the mesh's), reached (before it decided), tested (across the slab),
// clipped (left to the rational clip), clear (1 where no triangle meets the
// pyramid).  Read the ratios off one run (same process, same machine state);
// --benchmark_repetitions=2 times each thing twice (the noise floor).
//
//   ./analysis/benchmarks/nearcap_benchmarks --benchmark_filter='NearPlaneCondition|EyeCount'
#include <benchmark/benchmark.h>

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "nearcap/analysis/near_rectangle_pyramid.hpp"
#include "nearcap/exact/camera_space.hpp"
#include "nearcap/exact/eye_count.hpp"
#include "nearcap/exact/light_facing.hpp"
#include "nearcap/gl/eye_count.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/scene/scene.hpp"

namespace {

// A frame: a bundled scene (its occluder object 0, its light 0), the
// camera moved where `moved` (looking from `eye` along `forward`, up +y,
// fovy 60 degrees, `near`; far, width and height the scene's).  The eyes
// close to the surface lie 0.005 to 0.04 above a mesh vertex along its
// normal, near 0.05 (the scenes' own); they were picked among about 6,000
// such cameras per mesh (every 997th vertex; heights 0.005 to 0.04; near
// 0.05 to 0.2; looking along a tangent tilted 0 to 45 degrees off the
// surface, or down or up the normal) as those with the most triangles
// across the slab and none meeting the pyramid (along: tilt 0; away: up the
// normal at near 0.05); facing looks down the normal from 0.02 above the
// along frame's vertex.
struct FrameSpec {
  const char* name;
  const char* scene_file;
  bool moved;
  nearcap::Vec3d eye, forward;
  double near;
};

const std::array<FrameSpec, 10> kFrames{{
    {"bunny as drawn", "bunny.json", false, {}, {}, 0},
    {"bunny beside", "bunny.json", true, {-2, 0, 1}, {0, 0, -1}, 2},
    {"bunny along", "bunny.json", true, {-0.379003, 0.347969, -0.0647518}, {-0.891004, -0.39584, -0.222311}, 0.05},
    {"bunny away", "bunny.json", true, {-0.14108, -0.438284, 0.320075}, {0.255508, 0.195275, 0.946881}, 0.05},
    {"bunny facing", "bunny.json", true, {-0.379003, 0.347969, -0.0647518}, {0.453995, -0.77687, -0.436305}, 0.05},
    {"armadillo as drawn", "armadillo.json", false, {}, {}, 0},
    {"armadillo beside", "armadillo.json", true, {-3, 0.95, 1.5}, {0, 0, -1}, 3},
    {"armadillo along", "armadillo.json", true, {-0.545691, 0.629824, -0.0022709}, {0, -0.132274, -0.991213}, 0.05},
    {"armadillo away", "armadillo.json", true, {-0.229809, 1.05462, 0.0812243}, {-0.50564, -0.389914, -0.769607}, 0.05},
    {"armadillo facing",
     "armadillo.json",
     true,
     {-0.530522, 0.616904, -0.000546686},
     {0.758426, -0.646033, 0.0862107},
     0.05},
}};

struct Frame {
  nearcap::Scene scene;
  std::unique_ptr<nearcap::CameraSpaceScene> cs;
};

const Frame& frame(std::size_t k) {
  static std::vector<std::unique_ptr<Frame>> frames(kFrames.size());
  if (!frames[k]) {
    const FrameSpec& f = kFrames[k];
    auto out = std::make_unique<Frame>();
    out->scene = nearcap::load_scene(std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/" + f.scene_file);
    if (f.moved) {
      const nearcap::Camera& c = out->scene.camera;
      out->scene.camera =
          nearcap::look_at_camera(f.eye, f.eye + f.forward, {0, 1, 0}, 60, f.near, c.frustum.far, c.width, c.height);
    }
    out->cs = std::make_unique<nearcap::CameraSpaceScene>(out->scene);
    frames[k] = std::move(out);
  }
  return *frames[k];
}

void BM_NearPlaneCondition(benchmark::State& state) {
  const std::size_t k = static_cast<std::size_t>(state.range(0));
  const Frame& f = frame(k);
  nearcap::analysis::NearRectanglePyramidWork work;
  bool clear = false;
  for (auto _ : state) {
    work = {};
    clear = nearcap::analysis::occluder_clear_of_near_rectangle_pyramid(*f.cs, 0, f.scene.camera.frustum, &work);
    benchmark::DoNotOptimize(clear);
  }
  state.SetLabel(kFrames[k].name);
  state.counters["triangles"] = static_cast<double>(f.scene.objects[0].mesh->triangle_count());
  state.counters["reached"] = static_cast<double>(work.triangles);
  state.counters["tested"] = static_cast<double>(work.tested);
  state.counters["clipped"] = static_cast<double>(work.clipped);
  state.counters["clear"] = clear ? 1 : 0;
}

// As the candidate test computes it: the occluder's light facing, then the
// exact eye count over it.
void BM_ExactEyeCountWithFacing(benchmark::State& state) {
  const std::size_t k = static_cast<std::size_t>(state.range(0));
  const Frame& f = frame(k);
  std::size_t count = 0;
  for (auto _ : state) {
    std::vector<std::vector<nearcap::Facing>> facing(f.cs->object_count());
    facing[0] = nearcap::light_facing(*f.cs, 0, 0, nullptr);
    count = nearcap::exact_eye_count(*f.cs, 0, facing).count;
    benchmark::DoNotOptimize(count);
  }
  state.SetLabel(kFrames[k].name);
  state.counters["count"] = static_cast<double>(count);
}

void BM_FloatEyeCount(benchmark::State& state) {
  const std::size_t k = static_cast<std::size_t>(state.range(0));
  const Frame& f = frame(k);
  std::size_t count = 0;
  for (auto _ : state) {
    count = nearcap::gl::float_eye_count(f.scene, 0, {0}).count;
    benchmark::DoNotOptimize(count);
  }
  state.SetLabel(kFrames[k].name);
  state.counters["count"] = static_cast<double>(count);
}

BENCHMARK(BM_NearPlaneCondition)->DenseRange(0, kFrames.size() - 1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ExactEyeCountWithFacing)->DenseRange(0, kFrames.size() - 1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FloatEyeCount)->DenseRange(0, kFrames.size() - 1)->Unit(benchmark::kMillisecond);

}  // namespace
