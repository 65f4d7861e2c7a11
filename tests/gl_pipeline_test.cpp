// The software GL back end, the light frustum and the Figure 7 program.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "nearcap/gl/light_frustum.hpp"
#include "nearcap/gl/pipeline.hpp"
#include "nearcap/gl/shadow_vertex_programs.hpp"

namespace nearcap::gl {
namespace {

// A full-viewport quad at clip depth z (w = 1), counter-clockwise.
std::vector<Vec4f> full_quad(float z, bool ccw = true) {
  const Vec4f a{-1, -1, z, 1}, b{1, -1, z, 1}, c{1, 1, z, 1}, d{-1, 1, z, 1};
  if (ccw) return {a, b, c, a, c, d};
  return {a, c, b, a, d, c};
}

TEST(Framebuffer, StencilWrapsBothWays) {
  Framebuffer fb(4, 4, DepthFormat::Fixed24);
  DrawState s;
  s.depth_func = DepthFunc::Always;
  s.back.depth_pass = StencilOp::DecrementWrap;
  fb.draw(full_quad(0, false), s, {});
  for (std::uint8_t v : fb.stencil()) EXPECT_EQ(v, 255);
  s.front.depth_pass = StencilOp::IncrementWrap;
  for (int k = 0; k < 2; ++k) fb.draw(full_quad(0), s, {});
  for (std::uint8_t v : fb.stencil()) EXPECT_EQ(v, 1);
}

TEST(Framebuffer, DepthTestLessWithSeparateFailAndPassOps) {
  Framebuffer fb(8, 8, DepthFormat::Fixed24);
  DrawState write;
  write.depth_write = true;
  write.object_id = 7;
  fb.draw(full_quad(0.0f), write, {});  // z_w = 0.5
  for (std::int32_t o : fb.objects()) EXPECT_EQ(o, 7);
  DrawState count;
  count.front = {StencilOp::IncrementWrap, StencilOp::DecrementWrap};  // fail: +1, pass: -1
  fb.draw(full_quad(0.5f), count, {});                                 // behind: fails
  fb.draw(full_quad(0.0f), count, {});                                 // equal: LESS fails
  fb.draw(full_quad(-0.5f), count, {});                                // in front: passes
  for (std::uint8_t v : fb.stencil()) EXPECT_EQ(v, 1);
}

// The depth bounds test (GL_EXT_depth_bounds_test) passes a fragment where
// the depth stored at its pixel lies within [zmin, zmax], both ends
// included, and drops it elsewhere.
TEST(Framebuffer, DepthBoundsIncludeBothEnds) {
  for (DepthFormat format : {DepthFormat::Fixed24, DepthFormat::Float32}) {
    Framebuffer probe(1, 1, format);
    const std::uint32_t code = probe.encode_depth(0.5f);
    float f;
    std::memcpy(&f, &code, sizeof f);
    const double stored = format == DepthFormat::Fixed24 ? static_cast<double>(code) / 16777215.0 : f;
    auto counted = [&](std::array<double, 2> bounds) {
      Framebuffer fb(4, 4, format);
      fb.clear_depth(0.5f);
      DrawState s;
      s.depth_func = DepthFunc::Always;
      s.front.depth_pass = StencilOp::IncrementWrap;
      s.depth_bounds = bounds;
      const DrawCounters c = fb.draw(full_quad(0.0f), s, {});
      std::size_t ones = 0;
      for (std::uint8_t v : fb.stencil()) ones += v == 1 ? 1 : 0;
      EXPECT_EQ(c.fragments, ones);  // the fragments that reached the stencil test
      EXPECT_EQ(c.fragments + c.bounds_culled, 16u);
      return ones;
    };
    EXPECT_EQ(counted({stored, stored}), 16u) << "both ends at the stored depth";
    EXPECT_EQ(counted({0.0, stored}), 16u);
    EXPECT_EQ(counted({stored, 1.0}), 16u);
    EXPECT_EQ(counted({std::nextafter(stored, 1.0), 1.0}), 0u) << "above the stored depth";
    EXPECT_EQ(counted({0.0, std::nextafter(stored, 0.0)}), 0u) << "below it";
  }
}

TEST(Framebuffer, DepthEncodings) {
  const Framebuffer fixed(1, 1, DepthFormat::Fixed24), floating(1, 1, DepthFormat::Float32);
  EXPECT_EQ(fixed.encode_depth(1.0f), 0xFFFFFFu);
  EXPECT_EQ(fixed.encode_depth(0.0f), 0u);
  EXPECT_EQ(fixed.encode_depth(2.0f), 0xFFFFFFu);  // clamped to the depth range
  EXPECT_EQ(fixed.encode_depth(0.5f), 8388608u);   // 8388607.5 rounds to even
  EXPECT_EQ(fixed.encode_depth(0.25f), 4194304u);  // 4194303.75 rounds up
  // Two depths one float ulp apart: one 24-bit value, two float values.
  const float z = 0.25f, next = std::nextafter(z, 1.0f);  // 4194303.75 and 4194304.25 steps
  EXPECT_EQ(fixed.encode_depth(z), fixed.encode_depth(next));
  EXPECT_LT(floating.encode_depth(z), floating.encode_depth(next));
}

TEST(Framebuffer, CullingByFacing) {
  Framebuffer fb(4, 4, DepthFormat::Fixed24);
  DrawState s;
  s.depth_func = DepthFunc::Always;
  s.cull = CullFace::Back;
  s.front.depth_pass = s.back.depth_pass = StencilOp::IncrementWrap;
  const DrawCounters c = fb.draw(full_quad(0, false), s, {});
  EXPECT_EQ(c.culled, 2u);
  EXPECT_EQ(c.fragments, 0u);
  fb.draw(full_quad(0, true), s, {});
  for (std::uint8_t v : fb.stencil()) EXPECT_EQ(v, 1);
}

// With a guard band (RasterSettings::guard_band > 1, llvmpipe's way), a
// triangle wholly beside the viewport but inside the band is set up
// (rasterized) and covers nothing: it is not in view.  One whose bounds
// reach into the viewport by a sliver is, and so is one that covers it.
// Clipped at the view volume (the default band, 1), the one beside is
// clipped away.
TEST(Framebuffer, TrianglesInViewAreThoseWhoseBoundsMeetTheViewport) {
  Framebuffer fb(8, 8, DepthFormat::Fixed24);
  DrawState s;
  s.depth_func = DepthFunc::Always;
  s.front.depth_pass = s.back.depth_pass = StencilOp::IncrementWrap;
  RasterSettings band;
  band.guard_band = 64;
  auto triangle = [](float x0, float y0, float x1, float y1, float x2, float y2) {
    return std::vector<Vec4f>{{x0, y0, 0, 1}, {x1, y1, 0, 1}, {x2, y2, 0, 1}};
  };
  // NDC x in [1.5, 3]: window x from 10 to 16, right of the 8 pixels.
  const DrawCounters beside = fb.draw(triangle(1.5f, -0.5f, 3, -0.5f, 2, 0.5f), s, band);
  EXPECT_EQ(beside.rasterized, 1u);
  EXPECT_EQ(beside.in_view, 0u);
  EXPECT_EQ(beside.fragments, 0u);
  const DrawCounters clipped = fb.draw(triangle(1.5f, -0.5f, 3, -0.5f, 2, 0.5f), s, {});
  EXPECT_EQ(clipped.clipped, 1u);
  EXPECT_EQ(clipped.in_view, 0u);
  // Below the viewport, and above it.
  EXPECT_EQ(fb.draw(triangle(-0.5f, -3, 0.5f, -3, 0, -1.2f), s, band).in_view, 0u);
  EXPECT_EQ(fb.draw(triangle(-0.5f, 3, 0.5f, 3, 0, 1.2f), s, band).in_view, 0u);
  // Its left corner a quarter pixel inside the right edge (window x 7.75).
  const DrawCounters sliver = fb.draw(triangle(0.9375f, -0.5f, 3, -0.5f, 2, 0.5f), s, band);
  EXPECT_EQ(sliver.rasterized, 1u);
  EXPECT_EQ(sliver.in_view, 1u);
  const DrawCounters covering = fb.draw(full_quad(0), s, band);
  EXPECT_EQ(covering.in_view, 2u);
  EXPECT_EQ(covering.fragments, 64u);
}

TEST(Framebuffer, DepthClampKeepsWhatTheFarPlaneWouldClip) {
  DrawState s;
  s.depth_func = DepthFunc::Always;
  s.front.depth_pass = StencilOp::IncrementWrap;
  Framebuffer clipped(4, 4, DepthFormat::Fixed24), clamped(4, 4, DepthFormat::Fixed24);
  clipped.draw(full_quad(2.0f), s, {});  // beyond the far plane
  s.depth_clamp_far = true;
  clamped.draw(full_quad(2.0f), s, {});
  for (std::uint8_t v : clipped.stencil()) EXPECT_EQ(v, 0);
  for (std::uint8_t v : clamped.stencil()) EXPECT_EQ(v, 1);
}

Scene one_box_scene(const Vec3d& light, double near) {
  Scene scene;
  scene.camera.frustum = {-0.4, 0.4, -0.3, 0.3, near, 50};
  scene.camera.width = 64;
  scene.camera.height = 48;
  scene.lights.push_back({light});
  auto mesh = std::make_shared<TriangleMesh>();
  mesh->positions = {{-1, -1, -6}, {1, -1, -6}, {0, 1, -6}, {0, 0, -5}};
  mesh->triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}};
  SceneObject obj;
  obj.mesh = mesh;
  scene.objects.push_back(obj);
  return scene;
}

// The near rectangle's corners through M_l and P_l land on the light
// frustum's far rectangle at the camera's NDC corners.  float32: the matrices
// are rounded once from double, then two float products and a division; on
// these frames that is at most 6 ulps of 1 (3.6e-7), bounded at 2^-19 (32
// ulps).  z goes through the depth row's (f + n) / (f - n), at most 3 as
// l_near <= l_far / 2, so three times that.
void expect_far_rectangle_is_the_near_rectangle(const Scene& scene, const LightFrustum& lf) {
  const Frustum& f = scene.camera.frustum;
  for (double x : {f.left, f.right})
    for (double y : {f.bottom, f.top}) {
      const Vec4f corner{static_cast<float>(x), static_cast<float>(y), static_cast<float>(-f.near), 1.0f};
      const Vec4f c = transform(lf.projection, transform(lf.modelview, corner));
      EXPECT_NEAR(c.x / c.w, x < 0 ? -1.0 : 1.0, 0x1p-19);
      EXPECT_NEAR(c.y / c.w, y < 0 ? -1.0 : 1.0, 0x1p-19);
      EXPECT_NEAR(c.z / c.w, 1.0, 3 * 0x1p-19);  // the light's far plane
    }
}

// The infinite projection's depth row: exact puts a point at infinity on
// the far plane (z = w bit for bit, so far clipping keeps it), each nudge
// just inside it by its margin.
TEST(InfiniteProjection, EachNudgePutsInfinityWhereItSays) {
  Frustum f;
  f.left = -0.4;
  f.right = 0.4;
  f.bottom = -0.3;
  f.top = 0.3;
  f.near = 0.5;
  f.far = 100;
  const Vec4f direction{0.3f, -0.2f, -1.0f, 0.0f};  // away from the eye, at infinity
  auto ndc_z = [&](InfiniteFar nudge) {
    const Vec4f c = transform(infinite_frustum_matrix(f, nudge), direction);
    return double{c.z} / c.w;
  };
  const Vec4f exact = transform(infinite_frustum_matrix(f), direction);
  EXPECT_EQ(exact.z, exact.w);
  EXPECT_EQ(ndc_z(InfiniteFar::Epsilon), 1 - std::ldexp(1.0, -22));  // a float, reached exactly
  // 0.999 is no float: its rounding and the division's, under 2 ulps below 1 (2^-24).
  EXPECT_NEAR(ndc_z(InfiniteFar::Doom3), 0.999, 1e-7);
  EXPECT_LT(ndc_z(InfiniteFar::OneUlp), 1.0);
  EXPECT_GT(ndc_z(InfiniteFar::OneUlp), 1 - std::ldexp(1.0, -22));
  // The near plane stays where it is (z = -w at z_eye = -near; epsilon's
  // (eps - 2) n keeps it there) for all but doom3, which moves it to NDC
  // -1.001 (so a sliver in front of the near plane escapes clipping).
  for (InfiniteFar nudge : {InfiniteFar::Exact, InfiniteFar::Epsilon, InfiniteFar::Doom3, InfiniteFar::OneUlp}) {
    const Vec4f c = transform(infinite_frustum_matrix(f, nudge), {0, 0, -0.5f, 1});
    // The float32 depth row, a product and a division: 4 ulps of 1 (2^-23 each).
    EXPECT_NEAR(double{c.z} / c.w, nudge == InfiniteFar::Doom3 ? -1.001 : -1.0, 4 * 0x1p-23) << to_string(nudge);
    EXPECT_EQ(infinite_far_from_string(to_string(nudge)), nudge);
  }
}

TEST(LightFrustum, FarRectangleIsTheCameraNearRectangleOnBothSides) {
  for (LightProjection p :
       {LightProjection::Paper, LightProjection::GlFrustum, LightProjection::Composed, LightProjection::Rebased}) {
    LightFrustumChoice choice;
    choice.projection = p;
    const Scene same_side = one_box_scene({3, 2, 1}, 0.5);  // the camera's side of z = -0.5
    const LightFrustum a = light_frustum(same_side, 0, choice);
    ASSERT_TRUE(a.defined) << a.undefined_reason;
    EXPECT_EQ(a.alpha, 1);
    EXPECT_FLOAT_EQ(a.l_far, 1.5f);
    expect_far_rectangle_is_the_near_rectangle(same_side, a);
    const Scene other_side = one_box_scene({3, 2, -3}, 0.5);
    const LightFrustum b = light_frustum(other_side, 0, choice);
    ASSERT_TRUE(b.defined) << b.undefined_reason;
    EXPECT_EQ(b.alpha, -1);
    EXPECT_FLOAT_EQ(b.l_far, 2.5f);
    expect_far_rectangle_is_the_near_rectangle(other_side, b);
  }
}

// composed: P_l M_l in double maps the camera's near rectangle onto the
// light's far rectangle, x and y to +-1 and z to w, to double precision
// (a four-term product and a division: 1e-12 is thousands of eps).
TEST(LightFrustum, TheComposedMatrixMapsTheNearRectangleToTheFarRectangle) {
  LightFrustumChoice choice;
  choice.projection = LightProjection::Composed;
  for (const Vec3d& light : {Vec3d{3, 2, 1}, Vec3d{3, 2, -3}}) {
    const Scene scene = one_box_scene(light, 0.5);
    const LightFrustum lf = light_frustum(scene, 0, choice);
    ASSERT_TRUE(lf.defined) << lf.undefined_reason;
    const Frustum& f = scene.camera.frustum;
    for (double x : {f.left, f.right})
      for (double y : {f.bottom, f.top}) {
        const double p[4] = {x, y, -f.near, 1.0};
        double c[4] = {0, 0, 0, 0};
        for (int r = 0; r < 4; ++r)
          for (int k = 0; k < 4; ++k) c[r] += lf.composed[r][k] * p[k];
        EXPECT_NEAR(c[0] / c[3], x < 0 ? -1.0 : 1.0, 1e-12);
        EXPECT_NEAR(c[1] / c[3], y < 0 ? -1.0 : 1.0, 1e-12);
        EXPECT_NEAR(c[2] / c[3], 1.0, 1e-12);
      }
  }
}

// On a well-conditioned frame every formulation maps a point to the same NDC
// as the paper's matrix, within float32 rounding of a few operations
// (1e-5 of the NDC range).
TEST(LightFrustum, EveryFormulationAgreesWithThePaperOnAWellConditionedFrame) {
  const Scene scene = one_box_scene({3, 2, 1}, 0.5);
  const LightFrustum paper = light_frustum(scene, 0, {});
  ASSERT_TRUE(paper.defined);
  auto ndc = [](const LightFrustum& lf, LightProjection p, const Vec4f& v) {
    Vec4f c;
    if (p == LightProjection::Composed) {
      double d[4] = {0, 0, 0, 0};
      const double in[4] = {v.x, v.y, v.z, v.w};
      for (int r = 0; r < 4; ++r)
        for (int k = 0; k < 4; ++k) d[r] += lf.composed[r][k] * in[k];
      c = {static_cast<float>(d[0]), static_cast<float>(d[1]), static_cast<float>(d[2]), static_cast<float>(d[3])};
    } else {
      c = transform(lf.projection, transform(lf.modelview, v));
    }
    return std::array<double, 3>{c.x / c.w, c.y / c.w, c.z / c.w};
  };
  for (LightProjection p : {LightProjection::GlFrustum, LightProjection::Composed, LightProjection::Rebased}) {
    LightFrustumChoice choice;
    choice.projection = p;
    const LightFrustum lf = light_frustum(scene, 0, choice);
    ASSERT_TRUE(lf.defined);
    for (const Vec4f& v : {Vec4f{0.1f, 0.2f, -0.5f, 1}, Vec4f{-0.3f, 0.05f, -0.2f, 1}, Vec4f{1.2f, 0.9f, 0.4f, 1},
                           Vec4f{0.0f, 0.0f, -0.9f, 1}}) {
      const auto a = ndc(paper, LightProjection::Paper, v), b = ndc(lf, p, v);
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(a[k], b[k], 1e-5) << to_string(p) << " coordinate " << k;
    }
  }
}

TEST(LightFrustum, NearPlaneLeavesTheLightPyramidEmpty) {
  const Scene scene = one_box_scene({0, 1.5, -4}, 0.5);  // beyond the near plane, close to the box
  const LightFrustum lf = light_frustum(scene, 0, {});
  ASSERT_TRUE(lf.defined);
  EXPECT_GT(lf.l_near, 0.0f);
  EXPECT_LT(lf.l_near, lf.l_far);
  // Section 3.2: l_near = l_far d / d_max, so the farthest point of the light
  // near rectangle is d from the light: nothing of the occluder is closer.
  ASSERT_LT(lf.d, lf.d_max);
  // l_near is a float: its own rounding and that of the float product, 4 ulps.
  EXPECT_NEAR(lf.l_near, lf.l_far * lf.d / lf.d_max, 0x1p-22 * lf.l_far);
  EXPECT_NEAR(lf.d, distance_to_occluders(scene, {0, 1.5, -4}), 0.0);
  EXPECT_GT(lf.d, 0.0);
}

TEST(LightFrustum, UndefinedWhenTheLightIsInTheNearPlane) {
  const LightFrustum lf = light_frustum(one_box_scene({3, 2, -0.5}, 0.5), 0, {});
  EXPECT_FALSE(lf.defined);
  EXPECT_NE(lf.undefined_reason.find("near plane"), std::string::npos);
}

TEST(Figure7Program, ClippedMovableVerticesBecomeTheirNearCapCounterparts) {
  const Scene scene = one_box_scene({0, 3, -8}, 0.5);  // light beyond the box: shadows come at the camera
  const LightFrustum lf = light_frustum(scene, 0, {});
  ASSERT_TRUE(lf.defined);
  ShadowUniforms u;
  u.modelview_projection = frustum_matrix(scene.camera.frustum);  // view and model are the identity
  u.light_modelview = lf.modelview;
  u.light_projection = lf.projection;
  u.light_position = {0, 3, -8, 1};
  // A point between the eye and the near plane: clipped.
  const ShadowVertex movable{0.01f, 0.02f, -0.25f, 1.0f};
  const Vec4f out = figure7_program(u, movable);
  const Vec4f cap = near_cap_program(u, movable);
  EXPECT_EQ(out.x, cap.x);
  EXPECT_EQ(out.y, cap.y);
  EXPECT_EQ(out.w, cap.w);
  EXPECT_EQ(out.z, -out.w);  // on the near plane
  // Nailed (w = 2): kept where the camera puts it, clipped or not.
  const ShadowVertex nailed{0.01f, 0.02f, -0.25f, 2.0f};
  const Vec4f kept = figure7_program(u, nailed);
  const Vec4f plain = extrusion_program(u, movable);
  EXPECT_EQ(kept.x, plain.x);
  EXPECT_EQ(kept.z, plain.z);
  EXPECT_EQ(kept.w, plain.w);
  // A vertex the near plane does not clip is left alone.
  const ShadowVertex visible{0.0f, 0.0f, -3.0f, 1.0f};
  const Vec4f v = figure7_program(u, visible), e = extrusion_program(u, visible);
  EXPECT_EQ(v.x, e.x);
  EXPECT_EQ(v.z, e.z);
  // w = 0 extrudes away from the light: w_clip = -(z - l.z) < 0 here (towards the camera).
  const Vec4f extruded = extrusion_program(u, {0.0f, 0.0f, -3.0f, 0.0f});
  EXPECT_LT(extruded.w, 0.0f);
}

}  // namespace
}  // namespace nearcap::gl
