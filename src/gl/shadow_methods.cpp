// The shadow methods through the software pipeline (see shadow_methods.hpp):
// the frame renderer and the batch; what it draws with per object and per
// method is shadow_draw_setup.cpp.
#include "nearcap/gl/shadow_methods.hpp"

#include <chrono>
#include <cmath>
#include <deque>
#include <memory>
#include <optional>
#include <tuple>
#include <utility>

#include "mesh_vertex_array.hpp"
#include "nearcap/check.hpp"
#include "nearcap/error.hpp"
#include "nearcap/gl/engine_classification.hpp"
#include "nearcap/gl/eye_count.hpp"
#include "nearcap/gl/light_pyramid_cull.hpp"
#include "nearcap/gl/near_plane_cap.hpp"
#include "nearcap/gl/shadow_plan.hpp"
#include "nearcap/gl/shadow_volume_geometry.hpp"
#include "nearcap/gl/volume_bounds.hpp"
#include "shadow_draw_setup.hpp"
#include "shared_draws.hpp"

namespace nearcap::gl {
namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

// The per-object setup and per-method draw states (shadow_draw_setup.hpp).
using namespace draw_setup;

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
  std::deque<MeshVertexArray> meshes;  // per scene object, its address fixed (SharedDraws knows it by it)
  std::vector<std::optional<EngineSilhouette>> silhouettes;
  std::vector<std::optional<ShadowVolumeGeometry>> geometry;
  std::array<std::optional<DepthPass>, 2> depth;
  std::optional<LightFrustum> light_frustum;
  double light_frustum_ms = 0;
  double silhouette_ms = 0;                  // computing silhouettes and geometry, once
  std::vector<double> object_silhouette_ms;  // the same, per scene object
  SharedDraws draws;                         // the near-cap and volume draws' vertices and setups
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
        cap_kind_(near_cap_kind(settings.light_frustum.projection)),
        plans_(methods_.size(), nullptr) {
    NEARCAP_CHECK(methods_.size() == scene.objects.size());
    bool finite_needed = false, infinite_wanted = false, infinite_needed = false;
    for (std::size_t o = 0; o < methods_.size(); ++o) {
      if (!scene.objects[o].occluder) continue;
      const ShadowPlan& plan = shadow_plan(methods_[o], settings_.light_frustum.projection);
      plans_[o] = &plan;
      near_cap_pass_ = near_cap_pass_ || plan.cap_pass == CapPass::NearCap;
      eye_count_pass_ = eye_count_pass_ || plan.cap_pass == CapPass::EyeCount;
      light_frustum_needed_ =
          light_frustum_needed_ || (plan.cap_pass == CapPass::NearCap && plan.near_cap == NearCapKind::LightFrustum);
      finite_needed = finite_needed || plan.far_plane == FarPlane::FiniteNeeded;
      infinite_wanted = infinite_wanted || wants_infinite(plan.far_plane, settings_);
      infinite_needed = infinite_needed || plan.far_plane == FarPlane::InfiniteWanted;
    }
    // The infinite far plane when a method wants it (preload; Z-fail by
    // default; Z-pass, and ZP+ with the clipped-sides cap, which is Z-pass
    // plus a cap clipped by the sides' own projection, when asked) and no
    // method needs the finite one (ZP+'s light-frustum cap and case-D
    // switch: section 5.2).
    infinite_ = !finite_needed && infinite_wanted;
    if (finite_needed && infinite_needed)
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
    if (light_frustum_needed_) {  // clipped-sides needs no light frustum
      if (!shared_.light_frustum) {
        const auto t = Clock::now();
        shared_.light_frustum = light_frustum(scene_, light_, settings_.light_frustum);
        shared_.light_frustum_ms = ms_since(t);
      }
      frame.light_frustum = *shared_.light_frustum;
      frame.cpu.light_frustum_ms = shared_.light_frustum_ms;
      if (!frame.light_frustum.defined) frame.fallback = frame.light_frustum.undefined_reason;
    }
    const Mat4f projection =
        infinite_ ? infinite_frustum_matrix(scene_.camera.frustum, settings_.infinite_far, settings_.depth_mapping)
                  : frustum_matrix(scene_.camera.frustum, settings_.depth_mapping);
    prepare_objects(projection, frame);
    // Every method's setup includes the silhouettes and volume geometry, also
    // when an earlier method of the batch computed them.
    frame.times.setup_ms = ms_since(t_setup) - computed_here_ms_ + shared_.silhouette_ms;

    // The depth pre-pass: the same for every method with this projection.
    std::optional<SharedWork::DepthPass>& depth = shared_.depth[infinite_ ? 1 : 0];
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
        const MeshVertexArray& mesh = shared_.meshes[o];
        const std::vector<Vec4f> clip = run_vertex_program(VertexProgram::Extrusion, u, mesh.vertices);
        counters += fb.draw(clip, mesh.corner_vertex, oriented(s, objects_[o].mirrored), settings_.raster);
        if (settings_.record_draws)
          draws.push_back(program_draw(DrawPass::Depth, per_corner(clip, mesh.corner_vertex),
                                       oriented(s, objects_[o].mirrored), VertexProgram::Extrusion, GeometryPart::Mesh,
                                       corners(mesh), u));
      }
      depth = SharedWork::DepthPass{std::move(fb), counters, ms_since(t), std::move(draws)};
    }
    fb_ = depth->framebuffer;
    if (settings_.record_draws) frame.draws = depth->draws;
    frame.depth_pass = depth->counters;
    frame.times.depth_ms = depth->ms;

    auto t = Clock::now();
    reused_ms_ = 0;
    // AtomicZP's per-frame pass: the eye count over its occluders, the
    // stencil cleared to it (timed as the frame's cap pass: it stands where
    // ZP+'s near-cap pass stands).  It comes first, as glClearStencil does,
    // so that a frame mixing AtomicZP with ZP+ counts the near-cap on top.
    std::uint8_t eye_clear = 0;
    if (eye_count_pass_) {
      std::vector<std::size_t> counted;
      for (std::size_t o = 0; o < plans_.size(); ++o)
        if (plans_[o] && plans_[o]->cap_pass == CapPass::EyeCount) counted.push_back(o);
      const FloatEyeCount eye = float_eye_count(scene_, light_, counted, settings_.arithmetic);
      frame.eye_count = eye.count;
      frame.eye_count_triangles = eye.triangles;
      eye_clear = static_cast<std::uint8_t>(eye.count & 0xffu);
      fb_.clear_stencil(eye_clear);
    }
    if (near_cap_pass_ && frame.fallback.empty()) {
      near_cap_pass(frame);
      // The near-cap pass alone (the judge compares it with the exact cap).
      frame.near_cap = fb_.stencil();
      for (std::uint8_t& v : frame.near_cap) v = static_cast<std::uint8_t>(v - eye_clear);
    }
    frame.times.cap_ms = ms_since(t) + reused_ms_;

    t = Clock::now();
    reused_ms_ = 0;
    const ShadowPlan& zfail = shadow_plan(ShadowMethod::ZFail, settings_.light_frustum.projection);
    for (std::size_t o = 0; o < objects_.size(); ++o) {
      const ObjectSetup& obj = objects_[o];
      if (!obj.occluder) continue;
      const bool switched = switches_to_zfail(obj, frame);
      const ShadowPlan& plan = switched ? zfail : *plans_[o];
      // Z-fail's far plane: the method's own where the frame's projection
      // has it; a switch's clamp for a ZP+ method's switch, and for Z-fail
      // beside a ZP+ method (the finite projection: it clamps as the switch
      // does).
      const bool own_far = !switched && plan.far_plane == FarPlane::ZFailChoice &&
                           (infinite_ || settings_.zfail_far != ZFailFar::Infinite);
      const ZFailFar far = own_far ? settings_.zfail_far : as_zfail_far(settings_.switch_clamp);
      // ZF+: the far plane's cap, where there is a far plane, from the
      // clip-space vertices the volume was drawn with.
      const bool far_cap = far == ZFailFar::FarCap && !infinite_;
      std::vector<Vec4f> boundary;
      for (std::size_t k = 0; k < plan.draw_count; ++k) {
        const VolumeDraw& d = plan.draws[k];
        if (d.geometry == VolumeGeometry::FarPlaneCap) {
          if (far_cap) far_plane_cap(obj, boundary, frame);
          continue;
        }
        const bool keep = far_cap && d.count == VolumeCount::ZFail;
        draw(obj, geometry_part(d.geometry), d.program, volume_state(d.count, far, eye_clear), frame,
             keep ? &boundary : nullptr);
      }
    }
    frame.times.volume_ms = ms_since(t) + reused_ms_;
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
        if (plans_[o]->zfail_switch == ZFailSwitch::NoLightFrustumOrCaseD && obj.case_d && frame.fallback.empty())
          frame.zfail_objects.push_back(o);
      }
      if (shared_.meshes.size() <= o) shared_.meshes.push_back(mesh_vertex_array(*so.mesh));
      objects_.push_back(std::move(obj));
    }
  }

  // Whether the occluder draws the zfail row's volume instead of its
  // method's, and stays out of the near-cap pass.
  bool switches_to_zfail(const ObjectSetup& obj, const ShadowFrame& frame) const {
    switch (plans_[obj.index]->zfail_switch) {
      case ZFailSwitch::Never:
        return false;
      case ZFailSwitch::NoLightFrustum:
        return !frame.fallback.empty();
      case ZFailSwitch::NoLightFrustumOrCaseD:
        break;
    }
    return !frame.fallback.empty() || obj.case_d;
  }

  void near_cap_pass(ShadowFrame& frame) {
    if (cap_kind_ == NearCapKind::ClippedSides) {
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
      if (!obj.occluder || plans_[o]->cap_pass != CapPass::NearCap || switches_to_zfail(obj, frame)) continue;
      const DrawState state = bounded(oriented(s, obj.mirrored), obj);
      const IndexedInputs mesh = shared_.meshes[o].draw();
      frame.cap_pass += shared_draw(mesh, VertexProgram::NearCap, obj.uniforms, state);
      if (settings_.record_draws)
        frame.draws.push_back(
            program_draw(DrawPass::NearCap, shared_.draws.run(mesh, VertexProgram::NearCap, obj.uniforms).clip, state,
                         VertexProgram::NearCap, GeometryPart::Mesh, corners(shared_.meshes[o]), obj.uniforms));
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
      if (plans_[o]->cap_pass != CapPass::NearCap || switches_to_zfail(obj, frame)) continue;
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

  // A cap as an indexed draw of the mesh's points (light cap) or directions
  // (dark cap) (mesh_vertex_array.hpp): its corners, bit for bit; none for
  // the sides and corrective quads.
  std::optional<IndexedInputs> indexed_cap(const ObjectSetup& obj, GeometryPart part) const {
    const MeshVertexArray& mesh = shared_.meshes[obj.index];
    if (part == GeometryPart::LightCap) return IndexedInputs{mesh.vertices, obj.geometry->light_cap_vertex};
    if (part == GeometryPart::DarkCap) return IndexedInputs{mesh.directions, obj.geometry->dark_cap_vertex};
    return std::nullopt;
  }

  // `keep`: where to append the clip-space vertices too.
  void draw(const ObjectSetup& obj, GeometryPart part, VertexProgram program, const DrawState& s, ShadowFrame& frame,
            std::vector<Vec4f>* keep = nullptr) {
    const ShadowVolumeGeometry& g = *obj.geometry;
    const std::vector<ShadowVertex>& vertices = part == GeometryPart::Sides        ? g.sides
                                                : part == GeometryPart::Corrective ? g.corrective
                                                : part == GeometryPart::LightCap   ? g.light_cap
                                                                                   : g.dark_cap;
    const DrawState state = bounded(oriented(camera_state(s), obj.mirrored), obj);
    const std::optional<IndexedInputs> cap = indexed_cap(obj, part);
    frame.volume_pass +=
        cap ? shared_draw(*cap, program, obj.uniforms, state) : shared_draw(vertices, program, obj.uniforms, state);
    if (!keep && !settings_.record_draws) return;
    const std::vector<Vec4f>& clip = cap ? shared_.draws.run(*cap, program, obj.uniforms).clip
                                         : shared_.draws.run(vertices, program, obj.uniforms).clip;
    if (keep) keep->insert(keep->end(), clip.begin(), clip.end());
    if (settings_.record_draws)
      frame.draws.push_back(program_draw(DrawPass::Volume, clip, state, program, part, vertices, obj.uniforms));
  }

  // A draw of `program` on `inputs` through the batch's shared work: the
  // first method that draws them computes the clip-space vertices, their
  // setup and the fragments they cover; a later one with the same uniforms
  // and same_setup state replays those fragments with its own state, and is
  // charged the time they took (reused_ms_), so that each method's times
  // stay what drawing its frame alone takes.
  // `inputs`: a vertex array of the batch (volume geometry), or an indexed draw's
  // (mesh_vertex_array.hpp).
  template <class Inputs>
  DrawCounters shared_draw(const Inputs& inputs, VertexProgram program, const ShadowUniforms& u,
                           const DrawState& state) {
    const SharedDraws::SetUp set_up = shared_.draws.set_up(inputs, program, u, fb_, state, settings_.raster);
    reused_ms_ += set_up.reused_ms;
    DrawCounters counters = set_up.triangles.counters;
    const SharedDraws::Fragments fragments = shared_.draws.rasterize(set_up, fb_, state, settings_.raster);
    reused_ms_ += fragments.reused_ms;
    counters += fragments.counters;
    return counters;
  }

  // Volume culling: the occluder's scissor and depth bounds on a state of
  // its draws (all of them, so that the counts they drop add to 0; no depth
  // bounds for Z-pass where its region meets the near plane: volume_bounds.hpp).
  // AtomicZP is never bounded: its volumes count between the eye and the
  // near plane too, where the bounds (of the volume beyond the near plane)
  // do not reach.
  DrawState bounded(DrawState s, const ObjectSetup& obj) const {
    if (!obj.bounds) return s;
    const CullingUse use = plans_[obj.index]->culling;
    if (use == CullingUse::None) return s;
    const VolumeCulling c = settings_.volume_culling;
    if (c == VolumeCulling::Scissor || c == VolumeCulling::Both) s.scissor = obj.bounds->scissor;
    const bool near_plane_unbounded = use == CullingUse::NoDepthBoundsAtNearPlane && obj.bounds->meets_near_plane;
    if ((c == VolumeCulling::DepthBounds || c == VolumeCulling::Both) && !near_plane_unbounded)
      s.depth_bounds = std::array<double, 2>{obj.bounds->depth_min, obj.bounds->depth_max};
    return s;
  }

  // A camera pass's state in the frame's depth mapping: the reversed
  // mapping's clip planes, and GL_GREATER for GL_LESS.
  DrawState camera_state(DrawState s) const {
    s.depth_mapping = settings_.depth_mapping;
    s.clamp_w_min = static_cast<float>(scene_.camera.frustum.near * 1e-5);
    if (s.depth_mapping == DepthMapping::Reversed && s.depth_func == DepthFunc::Less) s.depth_func = DepthFunc::Greater;
    return s;
  }

  const Scene& scene_;
  std::size_t light_;
  ShadowMethod method_;
  std::vector<ShadowMethod> methods_;
  EmulationSettings settings_;
  SharedWork& shared_;
  double computed_here_ms_ = 0;  // of shared_.silhouette_ms
  double reused_ms_ = 0;         // of shared_.draws, found computed by this frame's draws
  Framebuffer fb_;
  NearCapKind cap_kind_;
  std::vector<const ShadowPlan*> plans_;  // each occluder's method's row; null for the other objects
  bool near_cap_pass_ = false, eye_count_pass_ = false, light_frustum_needed_ = false;
  bool infinite_ = false;  // the camera's projection has its far plane at infinity
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
