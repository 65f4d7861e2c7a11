// The shadow methods through the software pipeline (see shadow_methods.hpp).
#include "nearcap/gl/shadow_methods.hpp"

#include <glm/glm.hpp>

#include <chrono>
#include <cmath>
#include <memory>
#include <optional>
#include <tuple>
#include <utility>

#include "nearcap/check.hpp"
#include "nearcap/error.hpp"
#include "nearcap/gl/engine_classification.hpp"
#include "nearcap/gl/eye_count.hpp"
#include "nearcap/gl/light_pyramid_cull.hpp"
#include "nearcap/gl/near_plane_cap.hpp"
#include "nearcap/gl/shadow_volume_geometry.hpp"
#include "nearcap/gl/volume_bounds.hpp"

namespace nearcap::gl {
namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

// What the application prepares for one object.
struct ObjectSetup {
  ShadowUniforms uniforms;
  bool mirrored = false;  // the modelview reverses orientation: glFrontFace(GL_CW)
  bool occluder = false;
  const EngineSilhouette* silhouette = nullptr;  // in the batch's shared work
  const ShadowVolumeGeometry* geometry = nullptr;
  bool case_d = false;
  std::optional<VolumeBounds> bounds;  // EmulationSettings::volume_culling
  std::size_t index = 0;               // in the scene's objects
};

Vec4f light_in_object_space(const SceneObject& obj, const Vec3d& light) {
  glm::dmat4 m(1.0);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) m[c][r] = obj.object_to_world.rows[r][c];
  const glm::dvec4 p = glm::inverse(m) * glm::dvec4(light.x, light.y, light.z, 1.0);
  return {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z), 1.0f};
}

float determinant3(const Mat4f& m) {
  return m.at(0, 0) * (m.at(1, 1) * m.at(2, 2) - m.at(1, 2) * m.at(2, 1)) -
         m.at(0, 1) * (m.at(1, 0) * m.at(2, 2) - m.at(1, 2) * m.at(2, 0)) +
         m.at(0, 2) * (m.at(1, 0) * m.at(2, 1) - m.at(1, 1) * m.at(2, 0));
}

Mat4f identity_matrix() {
  Mat4f m;
  for (int k = 0; k < 4; ++k) m.at(k, k) = 1.0f;
  return m;
}

// (P_l M_l) * view * object_to_world, all in double, rounded to float32 once.
Mat4f composed_light_matrix(const LightFrustum& lf, const Affine3d& view, const Affine3d& object_to_world) {
  std::array<std::array<double, 4>, 4> mv{};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) {
      double v = c == 3 ? view.rows[r][3] : 0.0;
      for (int k = 0; k < 3; ++k) v += view.rows[r][k] * object_to_world.rows[k][c];
      mv[r][c] = v;
    }
  mv[3][3] = 1.0;
  Mat4f out;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) {
      double v = 0;
      for (int k = 0; k < 4; ++k) v += lf.composed[r][k] * mv[k][c];
      out.at(r, c) = static_cast<float>(v);
    }
  return out;
}

DrawState oriented(DrawState s, bool mirrored) {
  if (!mirrored) return s;
  std::swap(s.front, s.back);
  if (s.cull == CullFace::Back)
    s.cull = CullFace::Front;
  else if (s.cull == CullFace::Front)
    s.cull = CullFace::Back;
  return s;
}

template <class Program>
std::vector<Vec4f> run_each(const std::vector<ShadowVertex>& in, const ShadowUniforms& u, Program program) {
  std::vector<Vec4f> out(in.size());
  for (std::size_t k = 0; k < in.size(); ++k) out[k] = program(u, in[k]);
  return out;
}

std::vector<Vec4f> run_program(const std::vector<ShadowVertex>& in, const ShadowUniforms& u, VertexProgram program) {
  switch (program) {
    case VertexProgram::Extrusion:
      return run_each(in, u, extrusion_program);
    case VertexProgram::Figure7:
      return run_each(in, u, figure7_program);
    case VertexProgram::NearCap:
      return run_each(in, u, near_cap_program);
  }
  return {};
}

// A recorded draw call whose vertices `program` made from `in`.
DrawCall program_draw(DrawPass pass, std::vector<Vec4f> clip, const DrawState& s, VertexProgram program,
                      GeometryPart part, const std::vector<ShadowVertex>& in, const ShadowUniforms& u) {
  return {pass, std::move(clip), s, VertexProgramRun{program, part, in, u}};
}

std::vector<ShadowVertex> mesh_vertices(const TriangleMesh& mesh) {
  std::vector<ShadowVertex> out;
  out.reserve(3 * mesh.triangle_count());
  for (const auto& t : mesh.triangles)
    for (VertexIndex v : t) {
      const Vec3d& p = mesh.positions[v];
      out.push_back({static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z), 1.0f});
    }
  return out;
}

constexpr StencilOps kCountOnPass{StencilOp::Keep, StencilOp::IncrementWrap};
constexpr StencilOps kUncountOnPass{StencilOp::Keep, StencilOp::DecrementWrap};
constexpr StencilOps kCountOnFail{StencilOp::IncrementWrap, StencilOp::Keep};
constexpr StencilOps kUncountOnFail{StencilOp::DecrementWrap, StencilOp::Keep};
constexpr StencilOps kCountAlways{StencilOp::IncrementWrap, StencilOp::IncrementWrap};
constexpr StencilOps kUncountAlways{StencilOp::DecrementWrap, StencilOp::DecrementWrap};

DrawState zpass_state() {
  DrawState s;
  s.front = kCountOnPass;
  s.back = kUncountOnPass;
  return s;
}
// AtomicZP's volumes: Z-pass counting with GL_DEPTH_CLAMP, so that nothing
// is clipped at the near plane (the crossings between the eye and the near
// plane pass the depth test at the clamped depth) nor at the far one.
DrawState atomiczp_state(std::uint8_t eye_count) {
  DrawState s = zpass_state();
  s.depth_clamp_near = true;
  s.depth_clamp_far = true;
  s.stencil_clear = eye_count;
  return s;
}
DrawState zfail_state(ZFailFar far) {
  DrawState s;
  s.front = kUncountOnFail;
  s.back = kCountOnFail;
  s.depth_clamp_near = far == ZFailFar::DepthClamp;
  s.depth_clamp_far = far == ZFailFar::DepthClamp || far == ZFailFar::DepthClampFar;
  s.far_first = far == ZFailFar::FarCap;
  return s;
}

}  // namespace

// What every method of one (scene, light, settings) shares: the object-space
// vertex arrays, the engine's silhouettes and volume geometry, and the depth
// pre-pass per projection (finite far plane, or infinite for Z-fail's default
// and preload), with its counters and time.
struct ShadowFrameBatch::SharedWork {
  struct DepthPass {
    Framebuffer framebuffer;
    DrawCounters counters;
    double ms = 0;
    std::vector<DrawCall> draws;  // with record_draws
  };
  std::vector<std::vector<ShadowVertex>> vertices;
  std::vector<std::optional<EngineSilhouette>> silhouettes;
  std::vector<std::optional<ShadowVolumeGeometry>> geometry;
  std::array<std::optional<DepthPass>, 2> depth;
  std::optional<LightFrustum> light_frustum;
  double light_frustum_ms = 0;
  double silhouette_ms = 0;                  // computing silhouettes and geometry, once
  std::vector<double> object_silhouette_ms;  // the same, per scene object
};

namespace {

using SharedWork = ShadowFrameBatch::SharedWork;

class FrameRenderer {
 public:
  // `methods`: one per scene object (non-occluders' entries unused); the
  // frame reports `label` as its method.
  FrameRenderer(const Scene& scene, std::size_t light, ShadowMethod label, std::vector<ShadowMethod> methods,
                const EmulationSettings& settings, SharedWork& shared)
      : scene_(scene),
        light_(light),
        method_(label),
        methods_(std::move(methods)),
        settings_(settings),
        shared_(shared),
        fb_(scene.camera.width, scene.camera.height, settings.depth),
        clipped_sides_(settings.light_frustum.projection == LightProjection::ClippedSides) {
    NEARCAP_CHECK(methods_.size() == scene.objects.size());
    for (std::size_t o = 0; o < methods_.size(); ++o) {
      if (!scene.objects[o].occluder) continue;
      any_near_cap_ = any_near_cap_ || uses_near_cap(methods_[o]);
      any_preload_ = any_preload_ || methods_[o] == ShadowMethod::Preload;
      any_zpass_ = any_zpass_ || methods_[o] == ShadowMethod::ZPass || methods_[o] == ShadowMethod::AtomicZP;
      any_atomiczp_ = any_atomiczp_ || methods_[o] == ShadowMethod::AtomicZP;
      any_infinite_zfail_ =
          any_infinite_zfail_ || (methods_[o] == ShadowMethod::ZFail && settings_.zfail_far == ZFailFar::Infinite);
    }
    if (any_near_cap_ && any_preload_ && !clipped_sides_)
      throw Error(ErrorKind::Usage,
                  "preload cannot share a frame with a ZP+ method (preload needs the infinite projection, ZP+ the "
                  "finite one)");
  }

  ShadowFrame run() {
    ShadowFrame frame;
    frame.method = method_;
    frame.light = light_;
    frame.width = fb_.width();
    frame.height = fb_.height();
    for (std::size_t o = 0; o < methods_.size(); ++o)
      if (scene_.objects[o].occluder) frame.object_methods.push_back({o, methods_[o]});
    const auto t_setup = Clock::now();
    if (any_near_cap_ && !clipped_sides_) {  // clipped-sides needs no light frustum
      if (!shared_.light_frustum) {
        const auto t = Clock::now();
        shared_.light_frustum = light_frustum(scene_, light_, settings_.light_frustum);
        shared_.light_frustum_ms = ms_since(t);
      }
      frame.light_frustum = *shared_.light_frustum;
      frame.cpu.light_frustum_ms = shared_.light_frustum_ms;
      if (!frame.light_frustum.defined) frame.fallback = frame.light_frustum.undefined_reason;
    }
    // The infinite far plane when a method needs it (preload; Z-fail by
    // default; Z-pass, and ZP+ with the clipped-sides cap, which is Z-pass
    // plus a cap clipped by the sides' own projection, when asked) and no
    // ZP+ method needs the finite one (its light-frustum cap and case-D
    // switch: section 5.2).
    const bool finite_required = any_near_cap_ && !clipped_sides_;
    const bool infinite =
        !finite_required && (any_preload_ || any_infinite_zfail_ ||
                             ((any_zpass_ || any_near_cap_) && settings_.zpass_far == ZPassFar::Infinite));
    const Mat4f projection =
        infinite ? infinite_frustum_matrix(scene_.camera.frustum, settings_.infinite_far, settings_.depth_mapping)
                 : frustum_matrix(scene_.camera.frustum, settings_.depth_mapping);
    prepare_objects(projection, frame);
    // Every method's setup includes the silhouettes and volume geometry, also
    // when an earlier method of the batch computed them.
    frame.times.setup_ms = ms_since(t_setup) - computed_here_ms_ + shared_.silhouette_ms;

    // The depth pre-pass: the same for every method with this projection.
    std::optional<SharedWork::DepthPass>& depth = shared_.depth[infinite ? 1 : 0];
    if (!depth) {
      const auto t = Clock::now();
      Framebuffer fb(scene_.camera.width, scene_.camera.height, settings_.depth);
      if (settings_.depth_mapping == DepthMapping::Reversed) fb.clear_depth(0.0f);
      DrawCounters counters;
      std::vector<DrawCall> draws;
      for (std::size_t o = 0; o < objects_.size(); ++o) {
        DrawState s = camera_state({});
        s.depth_write = true;
        s.object_id = static_cast<std::int32_t>(o);
        const ShadowUniforms& u = objects_[o].uniforms;
        std::vector<Vec4f> clip = run_program(shared_.vertices[o], u, VertexProgram::Extrusion);
        counters += fb.draw(clip, oriented(s, objects_[o].mirrored), settings_.raster);
        if (settings_.record_draws)
          draws.push_back(program_draw(DrawPass::Depth, std::move(clip), oriented(s, objects_[o].mirrored),
                                       VertexProgram::Extrusion, GeometryPart::Mesh, shared_.vertices[o], u));
      }
      depth = SharedWork::DepthPass{std::move(fb), counters, ms_since(t), std::move(draws)};
    }
    fb_ = depth->framebuffer;
    if (settings_.record_draws) frame.draws = depth->draws;
    frame.depth_pass = depth->counters;
    frame.times.depth_ms = depth->ms;

    auto t = Clock::now();
    const bool zpplus = any_near_cap_ && frame.fallback.empty();
    if (zpplus) {
      near_cap_pass(frame);
      frame.near_cap = fb_.stencil();
    }
    // AtomicZP's per-frame pass: the eye count over its occluders, the
    // stencil cleared to it (timed as the frame's cap pass: it stands where
    // ZP+'s near-cap pass stands).
    std::uint8_t eye_clear = 0;
    if (any_atomiczp_) {
      std::vector<std::size_t> counted;
      for (std::size_t o = 0; o < methods_.size(); ++o)
        if (scene_.objects[o].occluder && methods_[o] == ShadowMethod::AtomicZP) counted.push_back(o);
      const FloatEyeCount eye = float_eye_count(scene_, light_, counted, settings_.arithmetic);
      frame.eye_count = eye.count;
      frame.eye_count_triangles = eye.triangles;
      eye_clear = static_cast<std::uint8_t>(eye.count & 0xffu);
      fb_.clear_stencil(eye_clear);
    }
    frame.times.cap_ms = ms_since(t);

    t = Clock::now();
    for (std::size_t o = 0; o < objects_.size(); ++o) {
      const ObjectSetup& obj = objects_[o];
      if (!obj.occluder) continue;
      const ShadowMethod m = methods_[o];
      if (m == ShadowMethod::AtomicZP) {
        draw(obj, GeometryPart::Sides, VertexProgram::Extrusion, atomiczp_state(eye_clear), frame);
      } else if (m == ShadowMethod::ZPass || (m == ShadowMethod::ZPPlus && zpplus)) {
        draw(obj, GeometryPart::Sides, VertexProgram::Extrusion, zpass_state(), frame);
      } else if (m == ShadowMethod::ZPPlusCorrected && zpplus && clipped_sides_) {
        draw(obj, GeometryPart::Sides, VertexProgram::Extrusion, zpass_state(), frame);
      } else if (m == ShadowMethod::ZPPlusCorrected && zpplus && !obj.case_d) {
        draw(obj, GeometryPart::Sides, VertexProgram::Figure7, zpass_state(), frame);
        draw(obj, GeometryPart::Corrective, VertexProgram::Figure7, zpass_state(), frame);
      } else if (m == ShadowMethod::Preload) {
        DrawState preload;
        preload.front = kUncountAlways;
        preload.back = kCountAlways;
        draw_closed_volume(obj, preload, frame);
        draw_closed_volume(obj, zpass_state(), frame);
      } else {
        // zfail, or a ZP+ method's switch to zfail (case D, or no light
        // frustum); Z-fail beside a ZP+ method has the finite projection, so
        // it clamps as the switch does.
        const bool own_far = m == ShadowMethod::ZFail && (infinite || settings_.zfail_far != ZFailFar::Infinite);
        const ZFailFar far = own_far ? settings_.zfail_far : as_zfail_far(settings_.switch_clamp);
        // ZF+: the far plane's cap, where there is a far plane, from the
        // clip-space vertices the volume was drawn with.
        const bool far_cap = far == ZFailFar::FarCap && !infinite;
        std::vector<Vec4f> boundary;
        draw_closed_volume(obj, zfail_state(far), frame, far_cap ? &boundary : nullptr);
        if (far_cap) far_plane_cap(obj, boundary, frame);
      }
    }
    frame.times.volume_ms = ms_since(t);
    frame.stencil = fb_.stencil();
    frame.object = fb_.objects();
    return frame;
  }

 private:
  void prepare_objects(const Mat4f& projection, ShadowFrame& frame) {
    const Mat4f view = to_mat4f(scene_.camera.view);
    const Arithmetic ar = settings_.arithmetic;
    for (std::size_t o = 0; o < scene_.objects.size(); ++o) {
      const SceneObject& so = scene_.objects[o];
      ObjectSetup obj;
      obj.index = o;
      const Mat4f modelview = multiply(view, to_mat4f(so.object_to_world), ar);
      obj.uniforms.modelview_projection = multiply(projection, modelview, ar);
      obj.uniforms.light_position = light_in_object_space(so, scene_.lights[light_].position);
      obj.uniforms.arithmetic = ar;
      obj.uniforms.depth_mapping = settings_.depth_mapping;
      if (frame.light_frustum.defined && settings_.light_frustum.projection == LightProjection::Composed) {
        // P_l * M_l * MV in double, rounded once: the whole light transform is one uploaded matrix.
        obj.uniforms.light_modelview =
            composed_light_matrix(frame.light_frustum, scene_.camera.view, so.object_to_world);
        obj.uniforms.light_projection = identity_matrix();
      } else if (frame.light_frustum.defined) {
        obj.uniforms.light_modelview = multiply(frame.light_frustum.modelview, modelview, ar);
        obj.uniforms.light_projection = frame.light_frustum.projection;
      }
      // A modelview that rounds to a singular float32 matrix (a view or an
      // object scale below float32's range, 1e-50 say) maps the object onto a
      // plane or a point: the exact kernel still answers, a GL cannot draw it.
      const float det = determinant3(modelview);
      if (!(det != 0.0f) || !std::isfinite(det))
        throw Error(ErrorKind::Range, scene_.source + ": objects[" + std::to_string(o) +
                                          "]: the modelview (view times object matrix) rounded to float32 is "
                                          "singular or not finite; the float pipeline cannot draw this object "
                                          "(scale the scene towards 1)");
      obj.mirrored = det < 0.0f;
      obj.occluder = so.occluder;
      if (so.occluder) {
        if (!shared_.silhouettes[o]) {
          const auto t = Clock::now();
          shared_.silhouettes[o] = engine_silhouette(scene_, o, light_);
          shared_.geometry[o] = shadow_volume_geometry(*so.mesh, *shared_.silhouettes[o]);
          const double ms = ms_since(t);
          shared_.silhouette_ms += ms;
          shared_.object_silhouette_ms[o] = ms;
          computed_here_ms_ += ms;
        }
        frame.cpu.occluders.push_back({o, shared_.object_silhouette_ms[o], 0.0});
        if (settings_.volume_culling != VolumeCulling::None)
          obj.bounds =
              shadow_volume_bounds(scene_, o, scene_.lights[light_].position, projection, settings_.depth_mapping);
        obj.silhouette = &*shared_.silhouettes[o];
        obj.geometry = &*shared_.geometry[o];
        for (QuadCase c : obj.silhouette->cases) {
          ++frame.float_cases[static_cast<std::size_t>(c)];
          obj.case_d = obj.case_d || c == QuadCase::D;
        }
        if (methods_[o] == ShadowMethod::ZPPlusCorrected && obj.case_d && frame.fallback.empty() && !clipped_sides_)
          frame.zfail_objects.push_back(o);
      }
      if (shared_.vertices.size() <= o) shared_.vertices.push_back(mesh_vertices(*so.mesh));
      objects_.push_back(std::move(obj));
    }
  }

  void near_cap_pass(ShadowFrame& frame) {
    if (clipped_sides_) {
      clipped_sides_cap_pass(frame);
      return;
    }
    DrawState s;
    s.depth_func = DepthFunc::Always;
    s.depth_clamp_near = frame.light_frustum.near_clamped;  // the near-clamp rule: no clipping at l_near
    s.cull = frame.light_frustum.alpha > 0 ? CullFace::Back : CullFace::Front;
    s.front = kCountAlways;
    s.back = kCountAlways;
    for (std::size_t o = 0; o < objects_.size(); ++o) {
      const ObjectSetup& obj = objects_[o];
      const ShadowMethod m = methods_[o];
      if (!obj.occluder || !uses_near_cap(m) || (m == ShadowMethod::ZPPlusCorrected && obj.case_d)) continue;
      std::vector<Vec4f> clip = run_program(shared_.vertices[o], obj.uniforms, VertexProgram::NearCap);
      frame.cap_pass += fb_.draw(clip, bounded(oriented(s, obj.mirrored), obj), settings_.raster);
      if (settings_.record_draws)
        frame.draws.push_back(program_draw(DrawPass::NearCap, std::move(clip), bounded(oriented(s, obj.mirrored), obj),
                                           VertexProgram::NearCap, GeometryPart::Mesh, shared_.vertices[o],
                                           obj.uniforms));
    }
  }

  // LightProjection::ClippedSides: per occluder, the fan over the edges the
  // near plane's clipping leaves of its closed volume (near_plane_cap.hpp),
  // +1 front, -1 back, no depth test; the same vertex program and uniforms
  // as its sides, so the fan shares their clipped edges bit for bit.
  void clipped_sides_cap_pass(ShadowFrame& frame) {
    DrawState s = camera_state(zpass_state());
    s.depth_func = DepthFunc::Always;
    s.vertices_on_near_plane = true;
    std::size_t occluder = 0;  // o's entry in frame.cpu.occluders
    for (std::size_t o = 0; o < objects_.size(); ++o) {
      const ObjectSetup& obj = objects_[o];
      if (!obj.occluder) continue;
      OccluderCpuTimes& cpu = frame.cpu.occluders[occluder++];
      if (!uses_near_cap(methods_[o])) continue;
      const auto t = Clock::now();
      std::vector<Vec4f> fan = clipped_sides_cap(obj);
      cpu.cap_build_ms = ms_since(t);
      if (fan.empty()) continue;
      const DrawState state = bounded(oriented(s, obj.mirrored), obj);
      frame.cap_pass += fb_.draw(fan, state, settings_.raster);
      if (settings_.record_draws) frame.draws.push_back({DrawPass::NearCap, std::move(fan), state, std::nullopt});
    }
  }

  // The clipped-sides cap of one occluder: the fan's clip-space vertices,
  // none where no part of its volume reaches the near plane (the CPU work a
  // renderer does for this cap, timed apart from its draw).
  std::vector<Vec4f> clipped_sides_cap(const ObjectSetup& obj) const {
    const std::size_t o = obj.index;
    const DepthMapping mapping = settings_.depth_mapping;
    // Only parts that may reach the near plane: the mesh's points (light
    // cap), its directions from the light (dark cap), and the sides
    // between them unless both lie strictly on one side.
    const TriangleMesh& mesh = *scene_.objects[o].mesh;
    const Vec3d &lo = mesh.face_planes.box_lo, &hi = mesh.face_planes.box_hi;  // the triangles' vertices
    const Vec4f& l = obj.uniforms.light_position;
    const Vec3d light{l.x, l.y, l.z};
    const int points = near_plane_side_of_box(obj.uniforms.modelview_projection, lo, hi, 1.0, mapping);
    const int directions =
        near_plane_side_of_box(obj.uniforms.modelview_projection, lo - light, hi - light, 0.0, mapping, light);
    // z + w (w - z reversed) of each mesh vertex as a point and as a
    // direction from the light, once per mesh vertex: bit for bit what the
    // program computes for it in any triangle (the same input, its z and w
    // rows) and the clipper then computes from them.
    const Mat4f& mvp = obj.uniforms.modelview_projection;
    auto near_distance = [&](const ShadowVertex& v) {
      const Vec4f in = extrusion_input(obj.uniforms, v);
      Vec4f clip;
      clip.z = transform_row(mvp, 2, in, obj.uniforms.arithmetic);
      clip.w = transform_row(mvp, 3, in, obj.uniforms.arithmetic);
      return near_plane_distance(clip, mapping);
    };
    // Both bounds strictly on one side: no part reaches the near plane.
    const bool sides_needed = points == 0 || directions == 0 || points != directions;
    if (!sides_needed) return {};
    // Nothing of the occluder in the light pyramid: an empty cap.
    if (settings_.cull_light_pyramid && certainly_misses_light_pyramid(scene_, o, scene_.lights[light_].position,
                                                                       near_plane_cap_margin(scene_.camera.width),
                                                                       near_plane_cap_margin(scene_.camera.height)))
      return {};
    std::vector<float> as_point(mesh.positions.size()), as_direction(mesh.positions.size());
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
      const Vec3d& p = mesh.positions[v];
      const float x = static_cast<float>(p.x), y = static_cast<float>(p.y), z = static_cast<float>(p.z);
      as_point[v] = near_distance({x, y, z, 1.0f});
      as_direction[v] = near_distance({x, y, z, 0.0f});
    }
    const ShadowVolumeGeometry& g = *obj.geometry;
    std::vector<Vec4f> boundary;
    for (const auto& [part, index, needed] :
         {std::tuple{&g.sides, &g.sides_vertex, true}, std::tuple{&g.light_cap, &g.light_cap_vertex, points == 0},
          std::tuple{&g.dark_cap, &g.dark_cap_vertex, directions == 0}}) {
      if (!needed) continue;
      // The whole program only for the triangles that reach the near plane.
      for (std::size_t t = 0; t + 2 < part->size(); t += 3) {
        bool beyond = true;
        for (std::size_t k = t; k < t + 3 && beyond; ++k)
          beyond = ((*part)[k].w == 0.0f ? as_direction : as_point)[(*index)[k]] > 0;
        if (beyond) continue;
        for (std::size_t k = t; k < t + 3; ++k) boundary.push_back(extrusion_program(obj.uniforms, (*part)[k]));
      }
    }
    if (boundary.empty()) return {};  // nothing reaches the near plane: no cap, no draw call
    return near_plane_cap_triangles(boundary, scene_.camera.width, scene_.camera.height, mapping);
  }

  // ZF+ (ZFailFar::FarCap): the far-plane cap of the occluder's closed
  // volume (near_plane_cap.hpp) over `boundary`, the clip-space vertices its
  // faces were drawn with; it closes the volume behind every visible
  // surface, so it is drawn without a depth test and counted as Z-fail
  // counts faces behind the surface (back +1, front -1).
  void far_plane_cap(const ObjectSetup& obj, const std::vector<Vec4f>& boundary, ShadowFrame& frame) {
    std::vector<Vec4f> cap =
        far_plane_cap_triangles(boundary, scene_.camera.width, scene_.camera.height, settings_.depth_mapping);
    if (cap.empty()) return;
    DrawState s = camera_state({});
    s.depth_func = DepthFunc::Always;
    s.front = kUncountAlways;
    s.back = kCountAlways;
    s.vertices_on_far_plane = true;
    const DrawState state = bounded(oriented(s, obj.mirrored), obj);
    frame.volume_pass += fb_.draw(cap, state, settings_.raster);
    if (settings_.record_draws) frame.draws.push_back({DrawPass::Volume, std::move(cap), state, std::nullopt});
  }

  // `keep`: where to append the clip-space vertices too.
  void draw(const ObjectSetup& obj, GeometryPart part, VertexProgram program, const DrawState& s, ShadowFrame& frame,
            std::vector<Vec4f>* keep = nullptr) {
    const ShadowVolumeGeometry& g = *obj.geometry;
    const std::vector<ShadowVertex>& vertices = part == GeometryPart::Sides        ? g.sides
                                                : part == GeometryPart::Corrective ? g.corrective
                                                : part == GeometryPart::LightCap   ? g.light_cap
                                                                                   : g.dark_cap;
    std::vector<Vec4f> clip = run_program(vertices, obj.uniforms, program);
    const DrawState state = bounded(oriented(camera_state(s), obj.mirrored), obj);
    frame.volume_pass += fb_.draw(clip, state, settings_.raster);
    if (keep) keep->insert(keep->end(), clip.begin(), clip.end());
    if (settings_.record_draws)
      frame.draws.push_back(
          program_draw(DrawPass::Volume, std::move(clip), state, program, part, vertices, obj.uniforms));
  }

  // Volume culling: the occluder's scissor and depth bounds on a state of
  // its draws (all of them, so that the counts they drop add to 0; no depth
  // bounds for Z-pass where its region meets the near plane: volume_bounds.hpp).
  // AtomicZP is never bounded: its volumes count between the eye and the
  // near plane too, where the bounds (of the volume beyond the near plane)
  // do not reach.
  DrawState bounded(DrawState s, const ObjectSetup& obj) const {
    if (!obj.bounds || methods_[obj.index] == ShadowMethod::AtomicZP) return s;
    const VolumeCulling c = settings_.volume_culling;
    if (c == VolumeCulling::Scissor || c == VolumeCulling::Both) s.scissor = obj.bounds->scissor;
    const bool zpass = methods_[obj.index] == ShadowMethod::ZPass;
    if ((c == VolumeCulling::DepthBounds || c == VolumeCulling::Both) && !(zpass && obj.bounds->meets_near_plane))
      s.depth_bounds = std::array<double, 2>{obj.bounds->depth_min, obj.bounds->depth_max};
    return s;
  }

  // A camera pass's state in the frame's depth mapping: the reversed
  // mapping's clip planes, and GL_GREATER for GL_LESS.
  DrawState camera_state(DrawState s) const {
    s.depth_mapping = settings_.depth_mapping;
    if (s.depth_mapping == DepthMapping::Reversed && s.depth_func == DepthFunc::Less) s.depth_func = DepthFunc::Greater;
    return s;
  }

  void draw_closed_volume(const ObjectSetup& obj, const DrawState& s, ShadowFrame& frame,
                          std::vector<Vec4f>* keep = nullptr) {
    draw(obj, GeometryPart::Sides, VertexProgram::Extrusion, s, frame, keep);
    draw(obj, GeometryPart::LightCap, VertexProgram::Extrusion, s, frame, keep);
    draw(obj, GeometryPart::DarkCap, VertexProgram::Extrusion, s, frame, keep);
  }

  const Scene& scene_;
  std::size_t light_;
  ShadowMethod method_;
  std::vector<ShadowMethod> methods_;
  bool any_near_cap_ = false, any_preload_ = false, any_infinite_zfail_ = false, any_zpass_ = false,
       any_atomiczp_ = false;
  EmulationSettings settings_;
  SharedWork& shared_;
  double computed_here_ms_ = 0;  // of shared_.silhouette_ms
  Framebuffer fb_;
  bool clipped_sides_;  // LightProjection::ClippedSides: the near-cap from the clipped volume, no light frustum
  std::vector<ObjectSetup> objects_;
};

}  // namespace

ZFailFar as_zfail_far(SwitchClamp c) {
  switch (c) {
    case SwitchClamp::DepthClamp:
      return ZFailFar::DepthClamp;
    case SwitchClamp::DepthClampFar:
      return ZFailFar::DepthClampFar;
    case SwitchClamp::FarCap:
      break;
  }
  return ZFailFar::FarCap;
}

bool uses_near_cap(ShadowMethod m) { return m == ShadowMethod::ZPPlus || m == ShadowMethod::ZPPlusCorrected; }

namespace {

std::unique_ptr<Scene> with_tight_near_plane(const Scene& scene, const EmulationSettings& settings, double& ms) {
  if (settings.near_plane != NearPlane::Tight) return nullptr;
  const auto t = Clock::now();
  auto tight = std::make_unique<Scene>(scene);
  tight->camera.frustum = tight_frustum(scene);
  ms = ms_since(t);
  return tight;
}

}  // namespace

ShadowFrameBatch::ShadowFrameBatch(const Scene& scene, std::size_t light, const EmulationSettings& settings)
    : tight_(with_tight_near_plane(scene, settings, tight_ms_)),
      scene_(tight_ ? *tight_ : scene),
      scene_near_(scene.camera.frustum.near),
      light_(light),
      settings_(settings),
      shared_(std::make_unique<SharedWork>()) {
  shared_->silhouettes.resize(scene.objects.size());
  shared_->geometry.resize(scene.objects.size());
  shared_->object_silhouette_ms.resize(scene.objects.size());
}
ShadowFrameBatch::~ShadowFrameBatch() = default;

ShadowFrame ShadowFrameBatch::render(ShadowMethod method) {
  ShadowFrame frame = FrameRenderer(scene_, light_, method, std::vector<ShadowMethod>(scene_.objects.size(), method),
                                    settings_, *shared_)
                          .run();
  frame.near = scene_.camera.frustum.near;
  frame.near_moved = frame.near != scene_near_;
  frame.times.setup_ms += tight_ms_;
  frame.cpu.near_plane_ms = tight_ms_;
  return frame;
}

ShadowFrame ShadowFrameBatch::render(const std::vector<ShadowMethod>& object_methods) {
  if (object_methods.size() != scene_.objects.size())
    throw Error(ErrorKind::Usage, "a method per scene object is needed: " + std::to_string(scene_.objects.size()) +
                                      " objects, " + std::to_string(object_methods.size()) + " methods");
  ShadowMethod label = ShadowMethod::ZPass;
  for (std::size_t o = 0; o < object_methods.size(); ++o)
    if (scene_.objects[o].occluder) {
      label = object_methods[o];
      break;
    }
  ShadowFrame frame = FrameRenderer(scene_, light_, label, object_methods, settings_, *shared_).run();
  frame.mixed = true;
  frame.near = scene_.camera.frustum.near;
  frame.near_moved = frame.near != scene_near_;
  frame.times.setup_ms += tight_ms_;
  frame.cpu.near_plane_ms = tight_ms_;
  return frame;
}

const LightFrustum& ShadowFrameBatch::light_frustum() {
  if (!shared_->light_frustum) {
    const auto t = Clock::now();
    shared_->light_frustum = gl::light_frustum(scene_, light_, settings_.light_frustum);
    shared_->light_frustum_ms = ms_since(t);
  }
  return *shared_->light_frustum;
}

ShadowFrame render_shadow_frame(const Scene& scene, std::size_t light, ShadowMethod method,
                                const EmulationSettings& settings) {
  return ShadowFrameBatch(scene, light, settings).render(method);
}

}  // namespace nearcap::gl
