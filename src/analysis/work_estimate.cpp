// The work estimate (see work_estimate.hpp).
#include "nearcap/analysis/work_estimate.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>

#include "affine_inverse.hpp"
#include "nearcap/analysis/screen_coverage.hpp"
#include "nearcap/check.hpp"
#include "nearcap/gl/light_pyramid_cull.hpp"
#include "nearcap/gl/near_plane_cap.hpp"

namespace nearcap::analysis {
namespace {

std::array<Vec3d, 8> box_corners(const Vec3d& lo, const Vec3d& hi) {
  std::array<Vec3d, 8> c;
  for (int k = 0; k < 8; ++k) c[k] = {(k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z};
  return c;
}

// Which side of the near plane all of `d` (near-plane distances) lie on:
// +1 all beyond it, -1 all in front, 0 straddling or within `margin`.
int side_of(const std::array<double, 8>& d, double margin) {
  bool beyond = true, in_front = true;
  for (double v : d) {
    beyond = beyond && v > margin;
    in_front = in_front && v < -margin;
  }
  return beyond ? 1 : in_front ? -1 : 0;
}

}  // namespace

std::string CandidateMethod::name() const {
  std::string n(gl::to_string(method));
  if (gl::uses_near_cap(method)) n += cap == gl::LightProjection::ClippedSides ? "-clipped-sides" : "-paper";
  return n;
}

OccluderWorkInputs occluder_work_inputs(const Scene& scene, std::size_t object, std::size_t light,
                                        const WorkInputsOptions& options) {
  const SceneObject& obj = scene.objects[object];
  const TriangleMesh& mesh = *obj.mesh;
  const Camera& camera = scene.camera;
  const double near = camera.frustum.near;
  OccluderWorkInputs in;
  in.object = object;
  in.triangles = static_cast<double>(mesh.triangle_count());

  // Facing, in object space, and the silhouette's edges, kept for the
  // sides' coverage below.
  const Vec3d l_object = inverse_apply(obj.object_to_world, scene.lights[light].position);
  std::optional<OccluderFacing> computed;
  if (!options.facings) computed = occluder_facing(mesh, l_object);
  const OccluderFacing& facing = options.facings ? options.facings->facing(obj.mesh, l_object) : *computed;
  const std::vector<std::uint8_t>& front = facing.front;
  const std::vector<std::array<VertexIndex, 2>>& edges = facing.edges;
  const std::size_t faces = mesh.triangle_count(), light_facing = facing.light_facing, silhouette = edges.size();
  in.light_facing = static_cast<double>(light_facing);
  in.silhouette_edges = static_cast<double>(silhouette);

  // Camera space: the box's corners (the near-plane tests), and a vertex as
  // a point or as a direction from the light where a coverage sum reads it.
  const Affine3d modelview = compose_rounded(camera.view, obj.object_to_world);
  const Vec3d l = camera.view.apply(scene.lights[light].position);
  std::array<double, 8> point_distance{}, direction_distance{};
  double magnitude = near;
  const auto corners = box_corners(mesh.face_planes.box_lo, mesh.face_planes.box_hi);
  for (int k = 0; k < 8; ++k) {
    const Vec3d c = modelview.apply(corners[k]);
    point_distance[k] = -c.z - near;
    direction_distance[k] = -(c.z - l.z);
    magnitude = std::max({magnitude, std::fabs(c.z), std::fabs(l.z)});
  }
  const ScreenCoverage coverage(camera);
  auto as_point = [&](VertexIndex v) {
    const Vec3d c = modelview.apply(mesh.positions[v]);
    return CameraPoint{c.x, c.y, c.z, 1};
  };
  auto as_direction = [&](VertexIndex v) {
    const Vec3d c = modelview.apply(mesh.positions[v]);
    return CameraPoint{c.x - l.x, c.y - l.y, c.z - l.z, 0};
  };

  // The clipped-sides cap builder's work (gl/shadow_methods.cpp,
  // clipped_sides_cap): nothing where every part of the volume is on one
  // side of the near plane or the occluder certainly misses the pyramid;
  // else the sides, and each cap whose bounds straddle the plane.  An
  // estimate, in double from the box's corners: the builder decides the
  // same question on the float32 program's inputs with a certified bound
  // (gl/near_plane_cap.hpp, near_plane_side_of_box); within this margin of
  // the plane the estimate counts the cap as built.
  const double margin = 1e-5 * magnitude;
  const int points = side_of(point_distance, margin), directions = side_of(direction_distance, margin);
  const bool sides_needed = points == 0 || directions == 0 || points != directions;
  // The pyramid cull, the dearest input, runs where the cap's work depends
  // on it or the caller asks.
  in.pyramid_cull_run = options.pyramid_cull || sides_needed;
  if (in.pyramid_cull_run) {
    std::size_t examined = 0;
    in.certainly_misses_light_pyramid = gl::certainly_misses_light_pyramid(
        scene, object, scene.lights[light].position, gl::near_plane_cap_margin(camera.width),
        gl::near_plane_cap_margin(camera.height), &examined);
    in.pyramid_cull_examined = static_cast<double>(examined);
  }
  in.reaches_near_plane = sides_needed;
  const bool cap_built = sides_needed && !in.certainly_misses_light_pyramid;
  if (cap_built)
    in.clipped_cap_tested = 2 * in.silhouette_edges + (points == 0 ? in.light_facing : 0) +
                            (directions == 0 ? in.triangles - in.light_facing : 0);

  // Each cap's coverage, from every face of a mesh of up to
  // kCoverageSamples faces, else from every k-th (scaled by k): its cost
  // bounded whatever the mesh.
  const std::size_t face_stride = std::max<std::size_t>(1, faces / kCoverageSamples);
  // The near-cap (where the cap is built): the light-facing triangles
  // between the light and the near plane, seen from the light on the near
  // rectangle (screen_coverage.hpp).  A light in the near plane has no such
  // view: the viewport stands for the cap.
  const bool near_cap_seen = cap_built && l.z + near != 0;
  if (cap_built && !near_cap_seen) in.near_cap_pixels = static_cast<double>(camera.width) * camera.height;
  std::optional<LightView> light_view;
  if (near_cap_seen) light_view.emplace(camera, l);
  auto seen_from_light = [&](VertexIndex v) { return light_view->vertex(modelview.apply(mesh.positions[v])); };
  for (std::size_t f = face_stride / 2; f < faces; f += face_stride) {
    const auto& t = mesh.triangles[f];
    const bool is_front = front[f];
    auto vertex = [&](VertexIndex v) { return coverage.vertex(is_front ? as_point(v) : as_direction(v)); };
    const std::array<ScreenVertex, 3> image{vertex(t[0]), vertex(t[1]), vertex(t[2])};
    const double pixels = coverage.pixels(image.data(), 3);
    (is_front ? in.light_cap_pixels : in.dark_cap_pixels) += static_cast<double>(face_stride) * pixels;
    (is_front ? in.light_cap_in_view : in.dark_cap_in_view) +=
        static_cast<double>(face_stride) * coverage.in_view_pieces(image.data(), 3, false);
  }
  if (near_cap_seen) {
    // The light-facing faces of the chunks whose box the light's view of
    // the near rectangle may hold (mesh.hpp, FacePlanes).
    const FacePlanes& planes = mesh.face_planes;
    std::vector<FaceIndex> seen;
    const std::size_t chunks = planes.chunk_box.size();
    for (std::size_t k = 0; k < chunks; ++k) {
      std::uint8_t outside = 0xFF;
      for (const Vec3d& corner : box_corners(planes.chunk_box[k][0], planes.chunk_box[k][1])) {
        const Vec3d c = modelview.apply(corner);
        outside &= light_view->vertex(c).outside;
      }
      if (outside) continue;
      const std::size_t end = std::min(planes.chunk_faces.size(), (k + 1) * FacePlanes::kFacesPerChunk);
      for (std::size_t i = k * FacePlanes::kFacesPerChunk; i < end; ++i)
        if (front[planes.chunk_faces[i]]) seen.push_back(planes.chunk_faces[i]);
    }
    if (chunks == 0)
      for (std::size_t f = 0; f < faces; ++f)
        if (front[f]) seen.push_back(static_cast<FaceIndex>(f));
    // A sample where many faces cover the cap; where few do (the light's
    // view of the near rectangle narrow), every face, each vertex seen once
    // and a face outside one plane of the view (all three vertices) costing
    // no area.
    const std::size_t stride = std::max<std::size_t>(1, seen.size() / kCoverageSamples);
    std::size_t hits = 0;
    for (std::size_t i = stride / 2; i < seen.size(); i += stride) {
      const auto& t = mesh.triangles[seen[i]];
      const std::array<ScreenVertex, 3> image{seen_from_light(t[0]), seen_from_light(t[1]), seen_from_light(t[2])};
      const double pixels = light_view->triangle_pixels(image[0], image[1], image[2]);
      in.near_cap_pixels += static_cast<double>(stride) * pixels;
      in.near_cap_in_view += static_cast<double>(stride) * light_view->in_view_pieces(image.data(), 3);
      hits += pixels > 0 ? 1 : 0;
    }
    if (stride > 1 && hits < kCoverageMinHits) {
      in.near_cap_pixels = in.near_cap_in_view = 0;
      std::vector<ScreenVertex> from_light_vertex(mesh.positions.size());
      std::vector<std::uint8_t> known(mesh.positions.size(), 0);
      auto light_vertex = [&](VertexIndex v) -> const ScreenVertex& {
        if (!known[v]) {
          from_light_vertex[v] = seen_from_light(v);
          known[v] = 1;
        }
        return from_light_vertex[v];
      };
      for (FaceIndex f : seen) {
        const auto& t = mesh.triangles[f];
        const ScreenVertex &a = light_vertex(t[0]), &b = light_vertex(t[1]), &c = light_vertex(t[2]);
        if (a.outside & b.outside & c.outside) continue;
        in.near_cap_pixels += light_view->triangle_pixels(a, b, c);
        const std::array<ScreenVertex, 3> image{a, b, c};
        in.near_cap_in_view += light_view->in_view_pieces(image.data(), 3);
      }
    }
  }
  // Each side: the quad (D,1) (A,1) (A,0) (D,0) of a silhouette edge,
  // every k-th of them (k = edges / kSideSamples, from the k/2-th) times k.
  // Their areas are uneven (a few near the eye, or nearly edge-on to the
  // light, can cover more than all the others), so the sum is rough; it is
  // the same for every candidate but AtomicZP's depth-clamped sides.
  const std::size_t edge_stride = std::max<std::size_t>(1, edges.size() / kSideSamples);
  for (std::size_t e = edge_stride / 2; options.sides_coverage && e < edges.size(); e += edge_stride) {
    const VertexIndex ea = edges[e][0], ed = edges[e][1];
    const std::array<ScreenVertex, 4> quad{coverage.vertex(as_point(ed)), coverage.vertex(as_point(ea)),
                                           coverage.vertex(as_direction(ea)), coverage.vertex(as_direction(ed))};
    const double near_clipped = coverage.pixels(quad.data(), 4);
    in.sides_pixels += static_cast<double>(edge_stride) * near_clipped;
    const double pieces = coverage.in_view_pieces(quad.data(), 4, false);
    in.sides_in_view += static_cast<double>(edge_stride) * pieces;
    in.sides_finite_far_in_view += static_cast<double>(edge_stride) * coverage.in_view_pieces(quad.data(), 4, true);
    // The same quad depth-clamped: the same pixels and pieces unless the
    // near plane cuts it; then its two triangles, unclipped, where they
    // cover pixels.
    const bool cut = (quad[0].outside | quad[1].outside | quad[2].outside | quad[3].outside) & 1u;
    const double clamped = cut ? coverage.pixels(quad.data(), 4, false) : near_clipped;
    in.sides_clamped_pixels += static_cast<double>(edge_stride) * clamped;
    in.sides_clamped_in_view += static_cast<double>(edge_stride) * (cut ? (clamped > 0 ? 2 : 0) : pieces);
  }
  if (!cap_built) return in;

  // The triangles that straddle the near plane: each side's quad as two
  // triangles, and where a cap's bounds straddle it, the cap's faces (the
  // light cap's as points, the dark cap's as directions from the light).
  // Only the camera-space z of a vertex decides: modelview.apply's third
  // row, in its order.  A chunk of faces (mesh.hpp, FacePlanes) whose box's
  // corners lie on one side of the plane by more than `margin`, as points or
  // as directions, holds no straddling face of that kind.
  const auto& z_row = modelview.rows[2];
  auto z_of = [&z_row](const Vec3d& p) { return z_row[0] * p.x + z_row[1] * p.y + z_row[2] * p.z + z_row[3]; };
  auto point_near = [&](VertexIndex v) { return -z_of(mesh.positions[v]) - near; };
  auto direction_near = [&](VertexIndex v) { return -(z_of(mesh.positions[v]) - l.z); };
  auto straddles = [](double a, double b, double c) {
    const bool any_beyond = a > 0 || b > 0 || c > 0, all_beyond = a > 0 && b > 0 && c > 0;
    return any_beyond && !all_beyond;
  };
  // A straddling triangle's section of the near plane (where its edges
  // cross it) meeting the near rectangle: the cap's fan piece for it is in
  // view.  Tested for the first kSectionsTested straddling triangles, then
  // for every kSectionStride-th, weighted by the stride.
  constexpr std::size_t kSectionsTested = 64, kSectionStride = 8;
  const Frustum& frustum = camera.frustum;
  std::size_t straddling = 0;
  double fan_in_view = 0;
  auto tested = [&straddling] { return straddling <= kSectionsTested || straddling % kSectionStride == 0; };
  auto count_section = [&](const CameraPoint& a, const CameraPoint& b, const CameraPoint& c) {
    const double weight = straddling <= kSectionsTested ? 1.0 : static_cast<double>(kSectionStride);
    const std::array<CameraPoint, 3> v{a, b, c};
    double x_lo = INFINITY, x_hi = -INFINITY, y_lo = INFINITY, y_hi = -INFINITY;
    for (int k = 0; k < 3; ++k) {
      const CameraPoint &p = v[k], &q = v[(k + 1) % 3];
      const double dp = -p.z - near * p.w, dq = -q.z - near * q.w;
      if ((dp > 0) == (dq > 0)) continue;
      const double t = dp / (dp - dq), w = p.w + t * (q.w - p.w);
      if (!(w > 0)) continue;
      const double x = (p.x + t * (q.x - p.x)) / w, y = (p.y + t * (q.y - p.y)) / w;
      x_lo = std::min(x_lo, x);
      x_hi = std::max(x_hi, x);
      y_lo = std::min(y_lo, y);
      y_hi = std::max(y_hi, y);
    }
    if (x_hi >= frustum.left && x_lo <= frustum.right && y_hi >= frustum.bottom && y_lo <= frustum.top)
      fan_in_view += weight;
  };
  for (const auto& [ea, ed] : edges) {
    const double pd = point_near(ed), pa = point_near(ea), da = direction_near(ea), dd = direction_near(ed);
    if (straddles(pd, pa, da)) {
      straddling += 1;
      if (tested()) count_section(as_point(ed), as_point(ea), as_direction(ea));
    }
    if (straddles(pd, da, dd)) {
      straddling += 1;
      if (tested()) count_section(as_point(ed), as_direction(ea), as_direction(ed));
    }
  }
  auto count_face = [&](FaceIndex f, bool as_points, bool as_directions) {
    if (!(front[f] ? as_points : as_directions)) return;
    const auto& t = mesh.triangles[f];
    const bool crosses = front[f] ? straddles(point_near(t[0]), point_near(t[1]), point_near(t[2]))
                                  : straddles(direction_near(t[0]), direction_near(t[1]), direction_near(t[2]));
    if (!crosses) return;
    straddling += 1;
    if (!tested()) return;
    if (front[f])
      count_section(as_point(t[0]), as_point(t[1]), as_point(t[2]));
    else
      count_section(as_direction(t[0]), as_direction(t[1]), as_direction(t[2]));
  };
  const FacePlanes& planes = mesh.face_planes;
  if (planes.chunk_box.empty() || planes.chunk_faces.size() != faces) {
    for (std::size_t f = 0; f < faces; ++f) count_face(static_cast<FaceIndex>(f), points == 0, directions == 0);
  } else {
    for (std::size_t k = 0; k < planes.chunk_box.size(); ++k) {
      std::array<double, 8> chunk_points{}, chunk_directions{};
      const auto chunk_corners = box_corners(planes.chunk_box[k][0], planes.chunk_box[k][1]);
      for (int c = 0; c < 8; ++c) {
        const double z = z_of(chunk_corners[c]);
        chunk_points[c] = -z - near;
        chunk_directions[c] = -(z - l.z);
      }
      const bool as_points = points == 0 && side_of(chunk_points, margin) == 0;
      const bool as_directions = directions == 0 && side_of(chunk_directions, margin) == 0;
      if (!as_points && !as_directions) continue;
      const std::size_t end = std::min(faces, (k + 1) * FacePlanes::kFacesPerChunk);
      for (std::size_t i = k * FacePlanes::kFacesPerChunk; i < end; ++i)
        count_face(planes.chunk_faces[i], as_points, as_directions);
    }
  }
  in.near_plane_straddling = static_cast<double>(straddling);
  in.near_cap_fan_in_view = fan_in_view;
  return in;
}

CpuTaskWork clipped_cap_work(const OccluderWorkInputs& in) {
  CpuTaskWork w;
  w.runs = 1;
  w.triangles = 2 * in.silhouette_edges;
  w.reaching = in.reaches_near_plane ? in.triangles : 0;
  w.tested = in.clipped_cap_tested;
  w.straddling = in.near_plane_straddling;
  // The builder runs the cull where the volume reaches the near plane, and
  // there the estimate ran the same cull.
  w.examined = in.reaches_near_plane ? in.pyramid_cull_examined : 0;
  return w;
}

CpuTaskWork exact_test_work(const std::vector<OccluderWorkInputs>& occluders) {
  CpuTaskWork w;
  w.runs = 1;
  for (const OccluderWorkInputs& in : occluders) {
    w.triangles += in.triangles;
    w.reaching += in.reaches_near_plane ? in.triangles : 0;
    w.tested += in.pyramid_cull_run && !in.certainly_misses_light_pyramid ? in.triangles : 0;
    w.straddling += in.near_plane_straddling;
  }
  return w;
}

FrameWork occluder_work(const OccluderWorkInputs& in, const CandidateMethod& c) {
  FrameWork w;
  auto pass = [&w](PassKind k, double triangles, double fragments, double in_view) {
    const auto i = static_cast<std::size_t>(k);
    w.drawn[i] = true;
    w.triangles[i] += triangles;
    w.fragments[i] += fragments;
    w.in_view[i] += in_view;
  };
  const double sides = 2 * in.silhouette_edges;
  // Z-pass's and ZP+'s sides at their far plane; Z-fail's at an infinite one.
  const double zpass_sides_in_view =
      c.zpass_far == gl::ZPassFar::Finite ? in.sides_finite_far_in_view : in.sides_in_view;
  switch (c.method) {
    case gl::ShadowMethod::ZPass:
      pass(PassKind::Sides, sides, in.sides_pixels, zpass_sides_in_view);
      break;
    case gl::ShadowMethod::ZFail:
      pass(PassKind::Sides, sides, in.sides_pixels, in.sides_in_view);
      pass(PassKind::LightCap, in.light_facing, in.light_cap_pixels, in.light_cap_in_view);
      pass(PassKind::DarkCap, in.triangles - in.light_facing, in.dark_cap_pixels, in.dark_cap_in_view);
      break;
    case gl::ShadowMethod::AtomicZP:  // Z-pass's sides, depth-clamped, and the eye count over every triangle
      pass(PassKind::Sides, sides, in.sides_clamped_pixels, in.sides_clamped_in_view);
      w.eye_count.drawn = true;
      w.eye_count.triangles = in.triangles;  // the stencil write's fragments are the frame's (estimate_frame_work)
      break;
    case gl::ShadowMethod::Preload:  // the closed volume twice
      pass(PassKind::Sides, 2 * sides, 2 * in.sides_pixels, 2 * in.sides_in_view);
      pass(PassKind::LightCap, 2 * in.light_facing, 2 * in.light_cap_pixels, 2 * in.light_cap_in_view);
      pass(PassKind::DarkCap, 2 * (in.triangles - in.light_facing), 2 * in.dark_cap_pixels, 2 * in.dark_cap_in_view);
      break;
    case gl::ShadowMethod::ZPPlus:
    case gl::ShadowMethod::ZPPlusCorrected:
      pass(PassKind::Sides, sides, in.sides_pixels, zpass_sides_in_view);
      if (c.cap == gl::LightProjection::ClippedSides) {
        w.clipped_cap = clipped_cap_work(in);
        // The fan: about one triangle per straddling one.
        if (in.near_plane_straddling > 0)
          pass(PassKind::NearCap, in.near_plane_straddling, in.near_cap_pixels, in.near_cap_fan_in_view);
      } else {
        pass(PassKind::NearCap, in.triangles, in.near_cap_pixels, in.near_cap_in_view);
      }
      break;
  }
  return w;
}

FrameWork shared_frame_work(const Scene& scene, bool with_coverage) {
  FrameWork w;
  const auto depth = static_cast<std::size_t>(PassKind::Depth), lit = static_cast<std::size_t>(PassKind::Lit);
  w.drawn[depth] = w.drawn[lit] = true;
  const ScreenCoverage coverage(scene.camera);
  for (const SceneObject& obj : scene.objects) {
    const TriangleMesh& mesh = *obj.mesh;
    const double t = static_cast<double>(mesh.triangle_count());
    const Affine3d modelview = with_coverage ? compose_rounded(scene.camera.view, obj.object_to_world) : Affine3d{};
    const std::size_t stride = std::max<std::size_t>(1, mesh.triangles.size() / kCoverageSamples);
    auto vertex = [&](VertexIndex v) {
      const Vec3d c = modelview.apply(mesh.positions[v]);
      return coverage.vertex({c.x, c.y, c.z, 1});
    };
    double pixels = 0, in_view = 0;
    for (std::size_t f = stride / 2; with_coverage && f < mesh.triangles.size(); f += stride) {
      const auto& tri = mesh.triangles[f];
      const std::array<ScreenVertex, 3> image{vertex(tri[0]), vertex(tri[1]), vertex(tri[2])};
      pixels += static_cast<double>(stride) * coverage.pixels(image.data(), 3);
      in_view += static_cast<double>(stride) * coverage.in_view_pieces(image.data(), 3, false);
    }
    w.triangles[depth] += t;
    w.fragments[depth] += pixels;
    w.in_view[depth] += in_view;
    w.triangles[lit] += t;
    w.fragments[lit] += pixels;
    w.in_view[lit] += in_view;
    if (obj.occluder) w.silhouette_triangles += t;
  }
  return w;
}

FrameWork estimate_frame_work(const Scene& scene, std::size_t light,
                              const std::vector<gl::ShadowMethod>& object_methods,
                              const gl::EmulationSettings& settings) {
  FrameWork w = shared_frame_work(scene);
  const gl::LightProjection cap = settings.light_frustum.projection == gl::LightProjection::ClippedSides
                                      ? gl::LightProjection::ClippedSides
                                      : gl::LightProjection::Paper;
  // The paper's cap has no light frustum with the light in the near plane:
  // its ZP+ occluders are drawn with Z-fail.
  const double l_far = scene.camera.view.apply(scene.lights[light].position).z + scene.camera.frustum.near;
  for (std::size_t o = 0; o < scene.objects.size() && o < object_methods.size(); ++o) {
    if (!scene.objects[o].occluder) continue;
    CandidateMethod c{object_methods[o], cap, settings.zpass_far};
    if (gl::uses_near_cap(c.method) && cap == gl::LightProjection::Paper && l_far == 0)
      c.method = gl::ShadowMethod::ZFail;
    w += occluder_work(occluder_work_inputs(scene, o, light), c);
  }
  if (w.eye_count.drawn) w.eye_count.fragments = static_cast<double>(scene.camera.width) * scene.camera.height;
  return w;
}

}  // namespace nearcap::analysis
