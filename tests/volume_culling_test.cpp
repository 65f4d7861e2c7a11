// Volume culling (gl/volume_bounds.hpp, EmulationSettings::volume_culling):
// each occluder's scissor rectangle and depth bounds hold every pixel its
// volume changes, so the stencil of every visible pixel is the one drawn
// without them; fewer fragments reach the stencil test; the real GL does
// the same (scissor on llvmpipe; depth bounds where the driver has them).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "cli_support.hpp"
#include "llvmpipe_fixture.hpp"
#include "nearcap/analysis/hard_case_sampler.hpp"
#include "nearcap/error.hpp"
#include "nearcap/gl/shadow_methods.hpp"
#include "nearcap/gl/volume_bounds.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/render/gl_frame_replay.hpp"
#include "support/sampled_scenes.hpp"

namespace nearcap {
namespace {

std::uint64_t volume_fragments(const gl::ShadowFrame& f) { return f.volume_pass.fragments + f.cap_pass.fragments; }

// The seen pixels (an object drawn there) whose stencil differs.
std::size_t seen_differences(const gl::ShadowFrame& a, const gl::ShadowFrame& b) {
  std::size_t n = 0;
  for (std::size_t p = 0; p < a.stencil.size(); ++p) n += a.object[p] >= 0 && a.stencil[p] != b.stencil[p];
  return n;
}

// `base` with every object, light and the camera moved by `shift` (the
// frame unchanged but for float32's rounding far from the origin).
Scene moved_by(const Scene& base, const Vec3d& shift) {
  Scene scene = base;
  for (SceneObject& o : scene.objects)
    for (int r = 0; r < 3; ++r) o.object_to_world.rows[r][3] += shift[r];
  for (Light& l : scene.lights) l.position = l.position + shift;
  Affine3d& view = scene.camera.view;  // x -> L (x - shift) + c
  for (int r = 0; r < 3; ++r)
    view.rows[r][3] -= view.rows[r][0] * shift.x + view.rows[r][1] * shift.y + view.rows[r][2] * shift.z;
  return scene;
}

TEST(VolumeBounds, HoldEveryPixelTheVolumeChanges) {
  // The default scene: one occluder over a receiver.  Its bounds against
  // the seen pixels where Z-fail's stencil (right there) is not 0.
  const Scene scene = load_scene(std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/default.json");
  gl::EmulationSettings settings;
  const gl::ShadowFrame f = gl::render_shadow_frame(scene, 0, gl::ShadowMethod::ZFail, settings);
  const gl::Mat4f projection = gl::infinite_frustum_matrix(scene.camera.frustum, settings.infinite_far);
  std::size_t shadowed = 0;
  for (std::size_t o = 0; o < scene.objects.size(); ++o) {
    if (!scene.objects[o].occluder) continue;
    const std::optional<gl::VolumeBounds> b =
        gl::shadow_volume_bounds(scene, o, scene.lights[0].position, projection, gl::DepthMapping::Standard);
    ASSERT_TRUE(b.has_value());
    // Not the whole viewport: the bounds cull something.
    const long area = static_cast<long>(b->scissor.x1 - b->scissor.x0) * (b->scissor.y1 - b->scissor.y0);
    EXPECT_LT(area, static_cast<long>(f.width) * f.height);
    EXPECT_LT(b->depth_max - b->depth_min, 1.0);
    for (int j = 0; j < f.height; ++j)
      for (int i = 0; i < f.width; ++i)
        if (f.object[f.index(i, j)] >= 0 && f.stencil[f.index(i, j)] != 0) {
          ++shadowed;
          EXPECT_TRUE(b->scissor.contains(i, j)) << i << ", " << j;
        }
  }
  EXPECT_GT(shadowed, 100u);
}

TEST(VolumeBounds, NothingBoundedWithTheLightInTheOccludersBox) {
  Scene scene = load_scene(std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/default.json");
  std::size_t occluder = 0;
  while (!scene.objects[occluder].occluder) ++occluder;
  const FacePlanes& fp = scene.objects[occluder].mesh->face_planes;
  const Vec3d centre = 0.5 * (fp.box_lo + fp.box_hi);
  const gl::Mat4f projection = gl::frustum_matrix(scene.camera.frustum);
  EXPECT_FALSE(gl::shadow_volume_bounds(scene, occluder, scene.objects[occluder].object_to_world.apply(centre),
                                        projection, gl::DepthMapping::Standard)
                   .has_value());
}

// The region's margins against the premise they are derived from: a light
// and an occluder each moved by up to e (2^-20 of the largest coordinate,
// how far the float pipeline's light and mesh may lie from the exact ones)
// cast a volume every point of which, inside B (grown by e) and in front of
// the near plane, projects into the scissor rectangle and the depth range.
// The default scene moved 2^12 and 2^16 units out: at 2^16 the cone
// facets' margin (2 t_max e) is what holds these points, the rectangle's
// 2-pixel allowance being too small (the facets unmoved, the test fails).
TEST(VolumeBounds, HoldTheVolumeOfALightAndOccluderMovedByTheMargin) {
  const Scene base = load_scene(std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/default.json");
  std::mt19937_64 random(20261206);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto on_sphere = [&](double radius) {  // a point of the sphere of that radius about 0
    std::normal_distribution<double> normal;
    Vec3d v{normal(random), normal(random), normal(random)};
    return (radius / std::sqrt(dot(v, v))) * v;
  };
  for (const double offset : {0x1p12, 0x1p16}) {
    SCOPED_TRACE("offset " + std::to_string(offset));
    const Scene scene = moved_by(base, {offset, 0.5 * offset, -offset});
    const Affine3d& view = scene.camera.view;
    const gl::Mat4f projection = gl::infinite_frustum_matrix(scene.camera.frustum, gl::InfiniteFar::Exact);
    const Vec3d light = scene.lights[0].position;
    std::size_t occluder = 0;
    while (!scene.objects[occluder].occluder) ++occluder;
    const std::optional<gl::VolumeBounds> bounds =
        gl::shadow_volume_bounds(scene, occluder, light, projection, gl::DepthMapping::Standard);
    ASSERT_TRUE(bounds.has_value());

    // Q (the occluder's box in world space) and B (every object's box and the near rectangle).
    auto world_corners = [](const SceneObject& o) {
      std::array<Vec3d, 8> c;
      const Vec3d lo = o.mesh->face_planes.box_lo, hi = o.mesh->face_planes.box_hi;
      for (int k = 0; k < 8; ++k)
        c[k] = o.object_to_world.apply({k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z});
      return c;
    };
    const std::array<Vec3d, 8> q = world_corners(scene.objects[occluder]);
    std::vector<Vec3d> b_points;
    for (const SceneObject& o : scene.objects)
      for (const Vec3d& c : world_corners(o)) b_points.push_back(c);
    const Frustum& f = scene.camera.frustum;
    for (const double x : {f.left, f.right})
      for (const double y : {f.bottom, f.top}) {
        // The view is a rotation and a translation: world = R^T (camera - t).
        Vec3d w{0, 0, 0};
        const double camera[3] = {x, y, -f.near};
        for (int r = 0; r < 3; ++r)
          for (int a = 0; a < 3; ++a) w[a] += view.rows[r][a] * (camera[r] - view.rows[r][3]);
        b_points.push_back(w);
      }
    double magnitude = std::max({std::fabs(light.x), std::fabs(light.y), std::fabs(light.z)});
    Vec3d b_lo = b_points[0], b_hi = b_points[0];
    for (const Vec3d& p : b_points)
      for (int a = 0; a < 3; ++a) {
        b_lo[a] = std::min(b_lo[a], p[a]);
        b_hi[a] = std::max(b_hi[a], p[a]);
        magnitude = std::max(magnitude, std::fabs(p[a]));
      }
    const double e = 0x1p-20 * magnitude;

    // Points l' + t (p' - l'), t >= 1, p on an edge of Q (where the cone's
    // facets lie), l' and p' at distance e from l and p.
    const int width = scene.camera.width, height = scene.camera.height;
    std::size_t checked = 0;
    for (int k = 0; k < 200000; ++k) {
      const int corner = static_cast<int>(random() % 8), other = corner ^ (1 << (random() % 3));
      const double u = unit(random);
      const Vec3d p = (1 - u) * q[corner] + u * q[other];
      const Vec3d moved_light = light + on_sphere(e), moved_p = p + on_sphere(e);
      const Vec3d x = moved_light + (1 + 4 * unit(random)) * (moved_p - moved_light);
      bool in_b = true;
      for (int a = 0; a < 3; ++a) in_b = in_b && x[a] >= b_lo[a] - e && x[a] <= b_hi[a] + e;
      if (!in_b) continue;
      const Vec3d c = view.apply(x);
      const double in[4] = {c.x, c.y, c.z, 1.0};
      double clip[4];
      for (int r = 0; r < 4; ++r) {
        clip[r] = 0;
        for (int col = 0; col < 4; ++col) clip[r] += double{projection.at(r, col)} * in[col];
      }
      if (!(clip[3] > 0) || clip[2] + clip[3] < 0) continue;  // behind the eye or the near plane
      const double wx = (clip[0] / clip[3] + 1) * 0.5 * width, wy = (clip[1] / clip[3] + 1) * 0.5 * height;
      if (wx < 0 || wy < 0 || wx >= width || wy >= height) continue;  // outside the viewport
      ++checked;
      const int i = static_cast<int>(std::floor(wx)), j = static_cast<int>(std::floor(wy));
      ASSERT_TRUE(bounds->scissor.contains(i, j))
          << "pixel " << i << ", " << j << " of the point " << x.x << ", " << x.y << ", " << x.z;
      const double depth = (clip[2] / clip[3] + 1) * 0.5;
      ASSERT_GE(depth, bounds->depth_min);
      ASSERT_LE(depth, bounds->depth_max);
    }
    EXPECT_GT(checked, 20000u);
  }
}

// Every bundled scene, light and method, each culling: the same stencil at
// every seen pixel, never more fragments, and fewer overall.
TEST(VolumeCulling, TheSameStencilOnEveryBundledScene) {
  std::uint64_t plain = 0, culled = 0;
  for (const char* name : {"default.json", "no_near_clip.json", "near_split.json", "twisted.json", "room.json",
                           "exact_camera.json", "room_side_light.json", "near_cap_bunny_silhouettes.json",
                           "eye_in_shadow.json", "far_grazing.json", "case_d.json", "light_on_near_plane.json"}) {
    const Scene scene = load_scene(std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/" + name);
    for (std::size_t light = 0; light < scene.lights.size(); ++light)
      for (gl::ShadowMethod m : gl::kAllShadowMethods) {
        const gl::ShadowFrame none = gl::render_shadow_frame(scene, light, m, {});
        plain += volume_fragments(none);
        for (gl::VolumeCulling c :
             {gl::VolumeCulling::Scissor, gl::VolumeCulling::DepthBounds, gl::VolumeCulling::Both}) {
          SCOPED_TRACE(std::string(name) + ", " + std::string(gl::to_string(m)) + ", " + std::string(gl::to_string(c)));
          gl::EmulationSettings settings;
          settings.volume_culling = c;
          const gl::ShadowFrame f = gl::render_shadow_frame(scene, light, m, settings);
          EXPECT_EQ(seen_differences(none, f), 0u);
          EXPECT_LE(volume_fragments(f), volume_fragments(none));
          EXPECT_EQ(volume_fragments(f) + f.volume_pass.bounds_culled + f.cap_pass.bounds_culled,
                    volume_fragments(none));
          if (c == gl::VolumeCulling::Both) culled += volume_fragments(f);
        }
      }
  }
  std::printf("[ culling  ] volume and near-cap fragments: %llu without, %llu with scissor and depth bounds\n",
              static_cast<unsigned long long>(plain), static_cast<unsigned long long>(culled));
  EXPECT_LT(culled * 10, plain * 9);  // at least a tenth fewer
}

// A slice of the hard-case sampler: the same stencil at every seen pixel
// for the methods whose float count is right outside the volume's region;
// ZP+ with the light frustum's cap can count a pixel outside it (its cap
// is drawn through another projection), and the culling then drops that
// wrong count: never a new wrong pixel.
TEST(VolumeCulling, OnASliceOfTheSampler) {
  const analysis::HardCaseSampler sampler(test::bundled_sampler_spec(7));
  std::size_t frames = 0;
  std::uint64_t plain = 0, culled = 0;
  test::for_each_sampled_scene(sampler, 150, [&](const Scene& scene, const analysis::HardCase& sample) {
    for (std::size_t light = 0; light < scene.lights.size(); ++light)
      for (gl::ShadowMethod m : gl::kAllShadowMethods) {
        gl::EmulationSettings settings;
        if (m == gl::ShadowMethod::ZPPlusCorrected)
          settings.light_frustum.projection = gl::LightProjection::ClippedSides;
        gl::ShadowFrame none, f;
        try {
          none = gl::render_shadow_frame(scene, light, m, settings);
          settings.volume_culling = gl::VolumeCulling::Both;
          f = gl::render_shadow_frame(scene, light, m, settings);
        } catch (const Error&) {
          continue;  // refused alike
        }
        ++frames;
        plain += volume_fragments(none);
        culled += volume_fragments(f);
        if (m != gl::ShadowMethod::ZPPlus) {
          EXPECT_EQ(seen_differences(none, f), 0u)
              << "sample " << sample.index << " light " << light << " " << to_string(m);
        }
      }
  });
  EXPECT_GT(frames, 500u);
  EXPECT_LT(culled * 4, plain * 3);  // at least a quarter fewer
}

// Configurations at 160 x 120 that test the region's cone: far from the
// origin (a million units out, where the float slack e is larger than the
// occluder's box, so a plane through the light with a corner of the box
// beyond it must not be taken for a facet), an eye in the shadow, a tiny
// near plane fitted tight.  Every method but ZP+ with the light frustum: the same
// stencil at every seen pixel.
TEST(VolumeCulling, WhereTheFloatVolumeLeavesTheExactOne) {
  struct Configuration {
    std::uint64_t seed, index;
    gl::NearPlane near_plane;
  };
  for (const Configuration c :
       {Configuration{13, 1429, gl::NearPlane::Scene}, Configuration{11, 702, gl::NearPlane::Scene},
        Configuration{21, 2739, gl::NearPlane::Tight}}) {
    analysis::SamplerSpec spec = test::bundled_sampler_spec(c.seed);
    spec.width = 160;
    spec.height = 120;
    const analysis::HardCaseSampler sampler(spec);
    const test::SampleWalk walk = test::for_each_sampled_scene(
        sampler, std::vector<std::uint64_t>{c.index}, [&](const Scene& scene, const analysis::HardCase&) {
          for (gl::ShadowMethod m : gl::kAllShadowMethods) {
            if (m == gl::ShadowMethod::ZPPlus) continue;
            SCOPED_TRACE("sample:" + std::to_string(c.seed) + ":" + std::to_string(c.index) + " " +
                         std::string(gl::to_string(m)));
            gl::EmulationSettings settings;
            settings.near_plane = c.near_plane;
            const gl::ShadowFrame none = gl::render_shadow_frame(scene, 0, m, settings);
            settings.volume_culling = gl::VolumeCulling::Both;
            const gl::ShadowFrame f = gl::render_shadow_frame(scene, 0, m, settings);
            EXPECT_EQ(seen_differences(none, f), 0u);
          }
        });
    EXPECT_EQ(walk.scenes, 1u);
  }
}

// Bundled scenes moved far from the origin (every object, the light and the
// camera by the same offset, up to 2^24, where float32 rounds positions to
// whole units), drawn at 160 x 120: every method but ZP+ with the light
// frustum keeps its stencil at every seen pixel.  The world-space margin e
// (2^-20 of the largest coordinate) is what this tests: without it the
// culling drops counts here.
TEST(VolumeCulling, FarFromTheOrigin) {
  std::size_t frames = 0;
  for (const char* name : {"default.json", "near_split.json", "eye_in_shadow.json"}) {
    const Scene base = load_scene(std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/" + name);
    for (const double offset : {0x1p10, 0x1p17, 0x1p20, 0x1p22, 0x1p24}) {
      Scene scene = moved_by(base, {offset, 0.5 * offset, -offset});
      scene.camera.width = 160;
      scene.camera.height = 120;
      for (gl::ShadowMethod m : gl::kAllShadowMethods) {
        if (m == gl::ShadowMethod::ZPPlus) continue;
        SCOPED_TRACE(std::string(name) + " at " + std::to_string(offset) + ", " + std::string(gl::to_string(m)));
        gl::EmulationSettings settings;
        gl::ShadowFrame none, f;
        try {
          none = gl::render_shadow_frame(scene, 0, m, settings);
          settings.volume_culling = gl::VolumeCulling::Both;
          f = gl::render_shadow_frame(scene, 0, m, settings);
        } catch (const Error&) {
          continue;  // refused alike (a frame float32 cannot hold)
        }
        ++frames;
        EXPECT_EQ(seen_differences(none, f), 0u);
      }
    }
  }
  EXPECT_GT(frames, 60u);
}

TEST(VolumeCulling, CommandLineChoice) {
  const test::CliResult bad = test::run_cli(
      "cracks " + std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/default.json --light 0 --volume-culling sometimes",
      "volume_culling_bad");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("volume-culling"), std::string::npos) << bad.err;
}

// The real GL with the scissor: llvmpipe's stencil is the emulation's, pixel
// for pixel, under the llvmpipe model; depth bounds need
// GL_EXT_depth_bounds_test, which llvmpipe lacks: a one-line error naming it.
class VolumeCullingGlTest : public test::LlvmpipeTest {};

TEST_F(VolumeCullingGlTest, TheScissorOnLlvmpipe) {
  std::size_t frames = 0;
  for (const char* name : {"default.json", "room.json", "near_split.json", "eye_in_shadow.json", "case_d.json"}) {
    const Scene scene = load_scene(std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/" + name);
    for (gl::ShadowMethod m : gl::kAllShadowMethods) {
      SCOPED_TRACE(std::string(name) + ", " + std::string(gl::to_string(m)));
      gl::EmulationSettings settings;
      settings.record_draws = true;
      settings.raster = gl::llvmpipe_model();
      settings.volume_culling = gl::VolumeCulling::Scissor;
      const gl::ShadowFrame modelled = gl::render_shadow_frame(scene, 0, m, settings);
      bool scissored = false;
      for (const gl::DrawCall& d : modelled.draws) scissored = scissored || d.state.scissor.has_value();
      EXPECT_EQ(scissored, m != gl::ShadowMethod::AtomicZP);  // AtomicZP's volumes are never bounded
      render::GlFrameReplay replay(modelled.width, modelled.height, settings.depth);
      const render::ReplayComparison c = render::compare(replay.replay(modelled.draws), modelled);
      EXPECT_EQ(c.stencil, 0u);
      EXPECT_EQ(c.near_cap, 0u);
      EXPECT_EQ(c.object, 0u);
      ++frames;
    }
  }
  EXPECT_EQ(frames, 30u);
}

TEST_F(VolumeCullingGlTest, DepthBoundsNeedTheExtension) {
  const Scene scene = load_scene(std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/default.json");
  gl::EmulationSettings settings;
  settings.record_draws = true;
  settings.volume_culling = gl::VolumeCulling::DepthBounds;
  const gl::ShadowFrame f = gl::render_shadow_frame(scene, 0, gl::ShadowMethod::ZFail, settings);
  render::GlFrameReplay replay(f.width, f.height, settings.depth);
  try {
    const render::ReplayComparison c = render::compare(replay.replay(f.draws), f);
    EXPECT_EQ(c.stencil, 0u);  // a driver with the extension: the same stencil
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Gl);
    EXPECT_NE(std::string(e.what()).find("GL_EXT_depth_bounds_test"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace nearcap
