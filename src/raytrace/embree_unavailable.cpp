// nearcap built without Embree (shadow_ray_tracer.hpp): the ray tracer says
// what to install instead of tracing.
#include "nearcap/error.hpp"
#include "nearcap/raytrace/shadow_ray_tracer.hpp"

namespace nearcap::raytrace {
namespace {

[[noreturn]] void unavailable() {
  throw Error(ErrorKind::Unavailable,
              "raytrace is unavailable: nearcap was built without Embree (install libembree-dev, e.g. with "
              "scripts/install-deps.sh, and rebuild)");
}

}  // namespace

bool raytrace_available() { return false; }

struct EmbreeScene::Impl {};

EmbreeScene::EmbreeScene(const Scene&) { unavailable(); }
EmbreeScene::~EmbreeScene() = default;
double EmbreeScene::build_ms() const { unavailable(); }
RaytraceFrame EmbreeScene::trace(std::size_t, const RaytraceSettings&) const { unavailable(); }

RaytraceFrame raytrace_shadows(const Scene&, std::size_t, const RaytraceSettings&) { unavailable(); }

}  // namespace nearcap::raytrace
