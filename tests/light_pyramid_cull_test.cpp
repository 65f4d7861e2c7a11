// The near-cap pass's light-pyramid filter (gl/light_pyramid_cull.hpp): it
// skips only occluders the exact kernel finds outside the light pyramid, and
// skipping leaves every frame as it was.
#include <gtest/gtest.h>

#include <string>

#include "nearcap/analysis/hard_case_sampler.hpp"
#include "nearcap/error.hpp"
#include "nearcap/exact/light_pyramid.hpp"
#include "nearcap/gl/light_pyramid_cull.hpp"
#include "nearcap/gl/near_plane_cap.hpp"
#include "nearcap/gl/shadow_methods.hpp"
#include "nearcap/io/scene_file.hpp"
#include "support/sampled_scenes.hpp"

namespace nearcap {
namespace {

// The exact camera form: the near rectangle is [-1, 1]^2 at z = -near, the
// light at z = 2 behind the eye; a box of side 2 * half at `centre`.
Scene box_scene(const std::string& centre, double half, double near) {
  return parse_scene(R"({"camera":{"view":[[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]],
    "frustum":{"left":-1,"right":1,"bottom":-1,"top":1,"near":)" +
                         std::to_string(near) + R"(,"far":100},"width":400,"height":400},
    "lights":[{"position":[0,0,2]}],"objects":[{"mesh":")" +
                         std::string(NEARCAP_SOURCE_DIR) + R"(/data/meshes/box.off","translate":)" + centre +
                         R"(,"scale":)" + std::to_string(2 * half) + "}]}",
                     "box scene", ".");
}

bool misses(const Scene& s) {
  return gl::certainly_misses_light_pyramid(s, 0, s.lights[0].position, gl::near_plane_cap_margin(400),
                                            gl::near_plane_cap_margin(400));
}

TEST(LightPyramidCull, SkipsOnlyWithTheMarginToSpare) {
  // The pyramid from (0, 0, 2) to [-1, 1]^2 at z = -1: at z = -0.9 its
  // half-width is 1 - 0.1 / 3.  The grown rectangle (margin 0.14 at 400
  // pixels) reaches 1.14 there.
  EXPECT_FALSE(misses(box_scene("[0,0,-0.9]", 0.05, 1)));     // on the axis
  EXPECT_FALSE(misses(box_scene("[1.06,0,-0.9]", 0.02, 1)));  // outside, but within the margin
  EXPECT_TRUE(misses(box_scene("[1.5,0,-0.9]", 0.02, 1)));    // well outside a side plane
  EXPECT_TRUE(misses(box_scene("[0,0,-3]", 0.5, 1)));         // beyond the near plane
  EXPECT_TRUE(misses(box_scene("[0,0,3]", 0.5, 1)));          // behind the light
  // A near plane below 2^-10 of the occluder's depth: never skipped (the
  // float32 cut of z + w is not trusted there).
  EXPECT_FALSE(misses(box_scene("[0,0,-30]", 0.5, 0.01)));
  EXPECT_TRUE(misses(box_scene("[0,0,-3]", 0.5, 0.5)));
}

// The faces it tests one by one: none where the mesh's box decides, one
// where the first face it tests may meet the pyramid (the box inside it),
// and no more than the mesh's faces on the sampler's scenes.
TEST(LightPyramidCull, CountsTheFacesItTestsOneByOne) {
  auto examined = [](const Scene& s) {
    std::size_t n = 12345;
    gl::certainly_misses_light_pyramid(s, 0, s.lights[0].position, gl::near_plane_cap_margin(400),
                                       gl::near_plane_cap_margin(400), &n);
    return n;
  };
  EXPECT_EQ(examined(box_scene("[1.5,0,-0.9]", 0.02, 1)), 0u);  // the mesh's box outside a side plane
  EXPECT_EQ(examined(box_scene("[0,0,-3]", 0.5, 1)), 0u);       // beyond the near plane
  EXPECT_EQ(examined(box_scene("[0,0,-0.9]", 0.05, 1)), 1u);    // inside: its first face may meet it
  EXPECT_EQ(examined(box_scene("[0,0,-30]", 0.5, 0.01)), 0u);   // not decided at all (tiny near)
  const analysis::HardCaseSampler sampler(test::bundled_sampler_spec(7));
  std::size_t counted = 0, several = 0;
  test::for_each_sampled_scene(sampler, 80, [&](const Scene& s, const analysis::HardCase&) {
    for (std::size_t light = 0; light < s.lights.size(); ++light)
      for (std::size_t o = 0; o < s.objects.size(); ++o) {
        std::size_t n = 0;
        const bool misses = gl::certainly_misses_light_pyramid(s, o, s.lights[light].position,
                                                               gl::near_plane_cap_margin(s.camera.width),
                                                               gl::near_plane_cap_margin(s.camera.height), &n);
        EXPECT_LE(n, s.objects[o].mesh->triangle_count());
        // Deciding "misses" face by face tests every face of the chunks it
        // could not decide whole; "may meet" stops at a face.
        if (!misses && n > 0) ++counted;
        if (misses && n > 1) ++several;
        EXPECT_EQ(misses, gl::certainly_misses_light_pyramid(s, o, s.lights[light].position,
                                                             gl::near_plane_cap_margin(s.camera.width),
                                                             gl::near_plane_cap_margin(s.camera.height)))
            << "the count changes no answer";
      }
  });
  std::printf("%zu occluders stopped at a face, %zu decided outside face by face\n", counted, several);
  EXPECT_GT(counted, 0u);
}

TEST(LightPyramidCull, ALightInTheNearPlaneIsNotDecided) {
  Scene s = box_scene("[0,0,-3]", 0.5, 1);
  s.lights[0].position = {0.3, 0.2, -1};
  EXPECT_FALSE(misses(s));
}

// Over every kind of the hard-case sampler: each skipped occluder meets no
// point of the exact pyramid, and the frame with the skip is the frame
// without it, stencil and near-cap alike.
TEST(LightPyramidCull, AgreesWithTheExactPyramidAndChangesNoFrame) {
  const analysis::HardCaseSampler sampler(test::bundled_sampler_spec(7));
  gl::EmulationSettings on;
  on.light_frustum.projection = gl::LightProjection::ClippedSides;
  gl::EmulationSettings off = on;
  off.cull_light_pyramid = false;
  std::size_t skipped = 0, kept = 0, frames = 0;
  test::for_each_sampled_scene(sampler, 160, [&](const Scene& s, const analysis::HardCase& sample) {
    const std::uint64_t k = sample.index;
    const CameraSpaceScene cs(s);
    for (std::size_t light = 0; light < s.lights.size(); ++light) {
      std::vector<bool> meets;
      try {
        meets = occluders_meeting_light_pyramid(cs, light);
      } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Degenerate);  // the light in the near plane
        continue;
      }
      bool any_skipped = false;
      for (std::size_t o = 0; o < s.objects.size(); ++o) {
        if (!s.objects[o].occluder) continue;
        const bool skip = gl::certainly_misses_light_pyramid(s, o, s.lights[light].position,
                                                             gl::near_plane_cap_margin(s.camera.width),
                                                             gl::near_plane_cap_margin(s.camera.height));
        if (skip) {
          EXPECT_FALSE(meets[o]) << "sample " << k << " light " << light << " object " << o;
        }
        skipped += skip;
        kept += !skip;
        any_skipped = any_skipped || skip;
      }
      if (!any_skipped) continue;
      gl::ShadowFrame a, b;
      try {
        a = gl::render_shadow_frame(s, light, gl::ShadowMethod::ZPPlusCorrected, on);
        b = gl::render_shadow_frame(s, light, gl::ShadowMethod::ZPPlusCorrected, off);
      } catch (const Error&) {
        continue;  // float32 transforms degenerate: refused alike
      }
      ++frames;
      EXPECT_EQ(a.stencil, b.stencil) << "sample " << k << " light " << light;
      EXPECT_EQ(a.near_cap, b.near_cap) << "sample " << k << " light " << light;
      EXPECT_LE(a.cap_pass.triangles, b.cap_pass.triangles);
    }
  });
  // Not vacuous: most occluders of the sampler stay clear of the pyramid.
  EXPECT_GT(skipped, 100u);
  EXPECT_GT(kept, 20u);
  EXPECT_GT(frames, 60u);
}

}  // namespace
}  // namespace nearcap
