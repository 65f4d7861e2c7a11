// The float ray tracer on Embree (see shadow_ray_tracer.hpp).
#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>

#include "nearcap/error.hpp"
#include "nearcap/raytrace/shadow_ray_tracer.hpp"

namespace nearcap::raytrace {
namespace {

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// The inverse of the view's linear part (double; the view is invertible:
// the scene reader checked it).
std::array<std::array<double, 3>, 3> inverse_linear(const Affine3d& a) {
  const auto& m = a.rows;
  const double c00 = m[1][1] * m[2][2] - m[1][2] * m[2][1], c01 = m[1][2] * m[2][0] - m[1][0] * m[2][2],
               c02 = m[1][0] * m[2][1] - m[1][1] * m[2][0];
  const double det = m[0][0] * c00 + m[0][1] * c01 + m[0][2] * c02;
  std::array<std::array<double, 3>, 3> inv{};
  inv[0] = {c00 / det, (m[0][2] * m[2][1] - m[0][1] * m[2][2]) / det, (m[0][1] * m[1][2] - m[0][2] * m[1][1]) / det};
  inv[1] = {c01 / det, (m[0][0] * m[2][2] - m[0][2] * m[2][0]) / det, (m[0][2] * m[1][0] - m[0][0] * m[1][2]) / det};
  inv[2] = {c02 / det, (m[0][1] * m[2][0] - m[0][0] * m[2][1]) / det, (m[0][0] * m[1][1] - m[0][1] * m[1][0]) / det};
  return inv;
}

Vec3d apply_linear(const std::array<std::array<double, 3>, 3>& m, const Vec3d& p) {
  return {m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z, m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z,
          m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z};
}

// Embree takes a ray only when its origin and direction are finite and within
// its float range (it asserts otherwise): beyond that, nearcap refuses.
constexpr float kEmbreeLarge = 1.8e18f;
bool representable(float x) { return std::fabs(x) < kEmbreeLarge; }  // false for NaN and infinities
bool representable(const float (&v)[3]) { return representable(v[0]) && representable(v[1]) && representable(v[2]); }

[[noreturn]] void refuse(const std::string& what) {
  throw Error(ErrorKind::Range, "raytrace: " + what +
                                    " is not finite in float32 (or beyond Embree's range, 1.8e18): the ray tracer "
                                    "cannot trace this frame");
}

// A shadow ray's context: the triangle it starts on, for the primitive-ID
// filter (Embree calls the filter with the context it was given).
struct ShadowRayContext {
  RTCIntersectContext base;
  unsigned geom = RTC_INVALID_GEOMETRY_ID, prim = RTC_INVALID_GEOMETRY_ID;
};

void ignore_own_triangle(const RTCFilterFunctionNArguments* args) {
  const auto* context = reinterpret_cast<const ShadowRayContext*>(args->context);
  for (unsigned k = 0; k < args->N; ++k) {
    if (args->valid[k] == 0) continue;
    if (RTCHitN_geomID(args->hit, args->N, k) == context->geom &&
        RTCHitN_primID(args->hit, args->N, k) == context->prim)
      args->valid[k] = 0;
  }
}

}  // namespace

bool raytrace_available() { return true; }

struct EmbreeScene::Impl {
  const Scene& scene;
  RTCDevice device = nullptr;
  RTCScene all = nullptr, occluders = nullptr;
  // Per object: world-space float vertices (x, y, z, plus one float of
  // padding at the end: Embree reads vertices as 16 bytes) and indices.
  std::vector<std::vector<float>> vertices;
  std::vector<std::vector<std::uint32_t>> indices;
  double build_ms = 0;
  std::string device_error;

  explicit Impl(const Scene& s) : scene(s) {}
  ~Impl() {
    if (all) rtcReleaseScene(all);
    if (occluders) rtcReleaseScene(occluders);
    if (device) rtcReleaseDevice(device);
  }

  void check(const char* step) const {
    const RTCError e = rtcGetDeviceError(device);
    if (e != RTC_ERROR_NONE)
      throw Error(e == RTC_ERROR_OUT_OF_MEMORY ? ErrorKind::Resource : ErrorKind::Range,
                  std::string("Embree: ") + step + " failed" + (device_error.empty() ? "" : ": " + device_error));
  }

  RTCGeometry geometry(std::size_t o) {
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, vertices[o].data(), 0,
                               3 * sizeof(float), (vertices[o].size() - 1) / 3);
    rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, indices[o].data(), 0,
                               3 * sizeof(std::uint32_t), indices[o].size() / 3);
    rtcCommitGeometry(g);
    return g;
  }
};

EmbreeScene::EmbreeScene(const Scene& scene) : impl_(std::make_unique<Impl>(scene)) {
  const auto t0 = std::chrono::steady_clock::now();
  Impl& s = *impl_;
  s.device = rtcNewDevice(nullptr);
  if (!s.device)
    throw Error(ErrorKind::Resource, "Embree: no device could be made (error " +
                                         std::to_string(static_cast<int>(rtcGetDeviceError(nullptr))) + ")");
  rtcSetDeviceErrorFunction(
      s.device, [](void* user, RTCError, const char* text) { static_cast<Impl*>(user)->device_error = text; }, &s);
  s.all = rtcNewScene(s.device);
  s.occluders = rtcNewScene(s.device);
  rtcSetSceneFlags(s.occluders, RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
  s.vertices.resize(scene.objects.size());
  s.indices.resize(scene.objects.size());
  for (std::size_t o = 0; o < scene.objects.size(); ++o) {
    const SceneObject& object = scene.objects[o];
    std::vector<float>& v = s.vertices[o];
    v.reserve(3 * object.mesh->positions.size() + 1);
    for (const Vec3d& p : object.mesh->positions) {
      const Vec3d w = object.object_to_world.apply(p);
      const float f[3] = {static_cast<float>(w.x), static_cast<float>(w.y), static_cast<float>(w.z)};
      if (!representable(f)) refuse("a world-space vertex of object " + std::to_string(o));
      v.insert(v.end(), {f[0], f[1], f[2]});
    }
    v.push_back(0.0f);
    std::vector<std::uint32_t>& t = s.indices[o];
    t.reserve(3 * object.mesh->triangles.size());
    for (const auto& tri : object.mesh->triangles) t.insert(t.end(), tri.begin(), tri.end());
    RTCGeometry g = s.geometry(o);
    rtcAttachGeometryByID(s.all, g, static_cast<unsigned>(o));
    rtcReleaseGeometry(g);
    if (object.occluder) {
      RTCGeometry h = s.geometry(o);
      rtcAttachGeometryByID(s.occluders, h, static_cast<unsigned>(o));
      rtcReleaseGeometry(h);
    }
  }
  rtcCommitScene(s.all);
  rtcCommitScene(s.occluders);
  s.check("building the BVHs");
  s.build_ms = ms_since(t0);
}

EmbreeScene::~EmbreeScene() = default;

double EmbreeScene::build_ms() const { return impl_->build_ms; }

RaytraceFrame EmbreeScene::trace(std::size_t light, const RaytraceSettings& settings) const {
  const Impl& s = *impl_;
  const Scene& scene = s.scene;
  if (light >= scene.lights.size())
    throw Error(ErrorKind::Usage, "light " + std::to_string(light) + " does not exist (the scene has " +
                                      std::to_string(scene.lights.size()) + ")");
  const auto t0 = std::chrono::steady_clock::now();
  const Camera& camera = scene.camera;
  RaytraceFrame f;
  f.light = light;
  f.width = camera.width;
  f.height = camera.height;
  const std::size_t n = static_cast<std::size_t>(f.width) * f.height;
  f.object.assign(n, -1);
  f.face.assign(n, 0);
  f.shadowed.assign(n, 0);

  // World space, double, then float: the eye, the light, and per pixel the
  // direction to its centre on the near plane.
  const auto inv = inverse_linear(camera.view);
  const Vec3d t{camera.view.rows[0][3], camera.view.rows[1][3], camera.view.rows[2][3]};
  const Vec3d eye_d = apply_linear(inv, Vec3d{-t.x, -t.y, -t.z});
  const float eye[3] = {static_cast<float>(eye_d.x), static_cast<float>(eye_d.y), static_cast<float>(eye_d.z)};
  const Vec3d& l = scene.lights[light].position;
  const float lp[3] = {static_cast<float>(l.x), static_cast<float>(l.y), static_cast<float>(l.z)};
  const Frustum& fr = camera.frustum;
  const float t_far = static_cast<float>(fr.far / fr.near);
  const ShadowEpsilon eps = settings.epsilon;
  if (!representable(eye)) refuse("the eye in world space");
  if (!representable(lp)) refuse("light " + std::to_string(light));
  if (!representable(t_far)) refuse("far / near");
  std::atomic<bool> unrepresentable{false};

  tbb::parallel_for(tbb::blocked_range<int>(0, f.height), [&](const tbb::blocked_range<int>& rows) {
    RTCIntersectContext primary_context;
    rtcInitIntersectContext(&primary_context);
    primary_context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    ShadowRayContext shadow_context;
    rtcInitIntersectContext(&shadow_context.base);
    if (eps == ShadowEpsilon::PrimitiveId) shadow_context.base.filter = ignore_own_triangle;
    for (int j = rows.begin(); j < rows.end(); ++j) {
      const double y = fr.bottom + (fr.top - fr.bottom) * (j + 0.5) / f.height;
      for (int i = 0; i < f.width; ++i) {
        const double x = fr.left + (fr.right - fr.left) * (i + 0.5) / f.width;
        const Vec3d d = apply_linear(inv, Vec3d{x, y, -fr.near});
        RTCRayHit rh;
        rh.ray.org_x = eye[0];
        rh.ray.org_y = eye[1];
        rh.ray.org_z = eye[2];
        rh.ray.dir_x = static_cast<float>(d.x);
        rh.ray.dir_y = static_cast<float>(d.y);
        rh.ray.dir_z = static_cast<float>(d.z);
        if (!representable(rh.ray.dir_x) || !representable(rh.ray.dir_y) || !representable(rh.ray.dir_z)) {
          unrepresentable = true;
          continue;
        }
        rh.ray.tnear = 1.0f;
        rh.ray.tfar = t_far;
        rh.ray.time = 0;
        rh.ray.mask = 0xffffffffu;
        rh.ray.id = 0;
        rh.ray.flags = 0;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(s.all, &primary_context, &rh);
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
        const std::size_t p = f.index(i, j);
        f.object[p] = static_cast<std::int32_t>(rh.hit.geomID);
        f.face[p] = rh.hit.primID;

        float q[3] = {rh.ray.org_x + rh.ray.tfar * rh.ray.dir_x, rh.ray.org_y + rh.ray.tfar * rh.ray.dir_y,
                      rh.ray.org_z + rh.ray.tfar * rh.ray.dir_z};
        if (eps != ShadowEpsilon::PrimitiveId) {
          // The unit normal on the side the primary ray came from.
          float nx = rh.hit.Ng_x, ny = rh.hit.Ng_y, nz = rh.hit.Ng_z;
          const float len = std::sqrt(nx * nx + ny * ny + nz * nz);
          const float side = (nx * rh.ray.dir_x + ny * rh.ray.dir_y + nz * rh.ray.dir_z) > 0 ? -1.0f : 1.0f;
          float offset = settings.fixed_offset;
          if (eps == ShadowEpsilon::Relative)
            offset = std::max(settings.relative_offset * std::max({std::fabs(q[0]), std::fabs(q[1]), std::fabs(q[2])}),
                              std::numeric_limits<float>::min());
          if (len > 0) {
            const float k = side * offset / len;
            nx *= k;
            ny *= k;
            nz *= k;
            q[0] += nx;
            q[1] += ny;
            q[2] += nz;
          }
        }
        const float to_light[3] = {lp[0] - q[0], lp[1] - q[1], lp[2] - q[2]};
        if (!representable(q) || !representable(to_light)) {
          unrepresentable = true;
          continue;
        }
        RTCRay shadow;
        shadow.org_x = q[0];
        shadow.org_y = q[1];
        shadow.org_z = q[2];
        shadow.dir_x = to_light[0];
        shadow.dir_y = to_light[1];
        shadow.dir_z = to_light[2];
        shadow.tnear = 0.0f;
        shadow.tfar = 1.0f;
        shadow.time = 0;
        shadow.mask = 0xffffffffu;
        shadow.id = 0;
        shadow.flags = 0;
        shadow_context.geom = rh.hit.geomID;
        shadow_context.prim = rh.hit.primID;
        rtcOccluded1(s.occluders, &shadow_context.base, &shadow);
        if (shadow.tfar < 0) f.shadowed[p] = 1;  // Embree sets tfar to -inf on a hit
      }
    }
  });
  if (unrepresentable) refuse("a pixel's primary or shadow ray");
  f.trace_ms = ms_since(t0);
  return f;
}

RaytraceFrame raytrace_shadows(const Scene& scene, std::size_t light, const RaytraceSettings& settings) {
  return EmbreeScene(scene).trace(light, settings);
}

}  // namespace nearcap::raytrace
