// The exact per-pixel reference (see pixel_reference.hpp for the forms).
#include "nearcap/exact/pixel_reference.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <chrono>

#include "pixel_tracer_impl.hpp"

namespace nearcap {
namespace {

double elapsed_ms(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - since).count();
}

}  // namespace

PixelReferenceTracer::PixelReferenceTracer(const CameraSpaceScene& scene, std::size_t light, LightSetupCache* cache,
                                           EyeSetupCache* eye_cache) {
  const auto t0 = std::chrono::steady_clock::now();
  impl_ = std::make_unique<Impl>(scene, light, cache, eye_cache);
  impl_->setup_ms = elapsed_ms(t0);
}
double PixelReferenceTracer::setup_ms() const { return impl_->setup_ms; }
PixelReferenceTracer::~PixelReferenceTracer() = default;

PixelSample PixelReferenceTracer::trace(int i, int j, FilterStats* stats) const {
  return impl_->trace(window_pixel_centre(i, j), true, stats);
}
PixelSample PixelReferenceTracer::trace_brute_force(int i, int j, FilterStats* stats) const {
  return impl_->trace(window_pixel_centre(i, j), false, stats);
}
const CentralGrid& PixelReferenceTracer::eye_grid() const { return *impl_->eye_grid; }
const CentralGrid& PixelReferenceTracer::light_grid() const { return *impl_->light_grid; }
std::size_t PixelReferenceTracer::front_facing_triangles() const { return impl_->lit.size(); }

PixelSample PixelReferenceTracer::trace_at(const WindowPoint& p, FilterStats* stats) const {
  return impl_->trace(p, true, stats);
}
const CameraSpaceScene& PixelReferenceTracer::scene() const { return impl_->cs; }
std::size_t PixelReferenceTracer::light() const { return impl_->light; }

namespace {

PixelReference trace_every_pixel(const PixelReferenceTracer& tracer, double setup_ms, PixelContent content) {
  const Scene& scene = tracer.scene().scene();
  PixelReference ref;
  ref.content = content;
  ref.light = tracer.light();
  ref.width = scene.camera.width;
  ref.height = scene.camera.height;
  const std::size_t n = static_cast<std::size_t>(ref.width) * static_cast<std::size_t>(ref.height);
  ref.cap.assign(n, 0);
  ref.stencil.assign(n, PixelReference::kNothingSeen);
  ref.object.assign(n, -1);
  ref.face.assign(n, 0);
  ref.setup_ms = setup_ms;

  const auto t1 = std::chrono::steady_clock::now();
  tbb::enumerable_thread_specific<FilterStats> stats;
  const std::size_t objects = tracer.scene().object_count();
  tbb::enumerable_thread_specific<std::vector<std::size_t>> cap_pixels(std::vector<std::size_t>(objects, 0));
  tbb::parallel_for(tbb::blocked_range<int>(0, ref.height), [&](const tbb::blocked_range<int>& rows) {
    FilterStats& local = stats.local();
    std::vector<std::size_t>& by_object = cap_pixels.local();
    std::uint32_t last_shadower = PixelReferenceTracer::Impl::kNoShadower;
    for (int j = rows.begin(); j < rows.end(); ++j)
      for (int i = 0; i < ref.width; ++i) {
        const PixelSample s = tracer.impl().trace(window_pixel_centre(i, j), true, &local, content, &last_shadower);
        const std::size_t k = ref.index(i, j);
        ref.cap[k] = s.cap;
        for (std::size_t c = 0; c < s.cap_objects.size(); ++c) ++by_object[s.cap_objects[c]];
        if (s.stencil) {
          ref.stencil[k] = *s.stencil;
          ref.object[k] = s.object;
          ref.face[k] = s.face;
        }
      }
  });
  for (const FilterStats& s : stats) ref.stats.merge(s);
  if (content == PixelContent::Full) ref.cap_pixels_by_object.assign(objects, 0);
  if (content == PixelContent::Full)
    for (const std::vector<std::size_t>& by_object : cap_pixels)
      for (std::size_t o = 0; o < objects; ++o) ref.cap_pixels_by_object[o] += by_object[o];
  ref.trace_ms = elapsed_ms(t1);
  return ref;
}

}  // namespace

PixelReference compute_pixel_reference(const CameraSpaceScene& scene, std::size_t light, PixelContent content) {
  const PixelReferenceTracer tracer(scene, light);
  return trace_every_pixel(tracer, tracer.setup_ms(), content);
}

PixelReference compute_pixel_reference(const PixelReferenceTracer& tracer, PixelContent content) {
  return trace_every_pixel(tracer, tracer.setup_ms(), content);
}

}  // namespace nearcap
