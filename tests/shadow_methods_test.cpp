// The float methods against the exact reference on bundled scenes: what
// issue 3 says must hold, and the explanations the README gives for each
// wrong pixel that remains.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <utility>

#include "box_scene.hpp"
#include "nearcap/gl/shadow_methods.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/judge/crack_map.hpp"
#include "nearcap/scene/scene.hpp"

namespace nearcap {
namespace {

using gl::ShadowMethod;

struct Judged {
  Scene scene;
  std::unique_ptr<CameraSpaceScene> cs;
  PixelReference ref;
};

// One exact reference per scene for the whole test program.
const Judged& judged(const std::string& name) {
  static std::map<std::string, std::unique_ptr<Judged>> cache;
  auto& slot = cache[name];
  if (!slot) {
    slot = std::make_unique<Judged>();
    slot->scene = load_scene(std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/" + name);
    slot->cs = std::make_unique<CameraSpaceScene>(slot->scene);
    slot->ref = compute_pixel_reference(*slot->cs, 0);
  }
  return *slot;
}

CrackReport judge(const std::string& name, ShadowMethod m, const gl::EmulationSettings& s = {}) {
  const Judged& j = judged(name);
  return judge_frame(gl::render_shadow_frame(j.scene, 0, m, s), j.ref);
}

// Does pixel p have a 4-neighbour whose exact shadow status differs?
bool on_shadow_boundary(const PixelReference& ref, int i, int j) {
  const int di[4] = {1, -1, 0, 0}, dj[4] = {0, 0, 1, -1};
  for (int k = 0; k < 4; ++k) {
    const int x = i + di[k], y = j + dj[k];
    if (x < 0 || y < 0 || x >= ref.width || y >= ref.height) continue;
    if (ref.shadowed(x, y) != ref.shadowed(i, j)) return true;
  }
  return false;
}

bool is_wrong(PixelVerdict v) { return v == PixelVerdict::WrongLit || v == PixelVerdict::WrongShadowed; }

TEST(ShadowMethods, ZPassIsWrongWhenTheEyeIsInShadowAndTheOthersAreRight) {
  const CrackReport zpass = judge("eye_in_shadow.json", ShadowMethod::ZPass);
  EXPECT_GT(zpass.pixels_seen, 100000u);
  EXPECT_GT(zpass.wrong, zpass.pixels_seen / 4) << "Z-pass misses the volume the eye is in";
  for (ShadowMethod m :
       {ShadowMethod::ZFail, ShadowMethod::ZPPlus, ShadowMethod::ZPPlusCorrected, ShadowMethod::Preload}) {
    const CrackReport r = judge("eye_in_shadow.json", m);
    EXPECT_EQ(r.wrong, 0u) << to_string(m);
    EXPECT_EQ(r.count_mismatch, 0u) << to_string(m);
  }
}

TEST(ShadowMethods, ZPassAndZFailAreRightOnAFaceInTheNearPlane) {
  // The face is drawn (GL's clip volume is closed at the near plane) and lit;
  // the reference sees it too, so the methods that count from the eye or from
  // infinity are right on every pixel.
  const Scene scene = test::near_plane_face();
  const PixelReference ref = compute_pixel_reference(CameraSpaceScene(scene), 0);
  for (ShadowMethod m : {ShadowMethod::ZPass, ShadowMethod::ZFail, ShadowMethod::Preload, ShadowMethod::AtomicZP}) {
    const CrackReport r = judge_frame(gl::render_shadow_frame(scene, 0, m), ref);
    EXPECT_EQ(r.pixels_seen, 64u * 48u) << to_string(m);
    EXPECT_EQ(r.wrong, 0u) << to_string(m);
    EXPECT_EQ(r.visibility_mismatch, 0u) << to_string(m);
  }
}

TEST(ShadowMethods, WithoutNearPlaneClippingEveryMethodIsWrongOnlyOnShadowBoundaries) {
  // No shadow volume reaches the near rectangle: the exact near-cap is empty.
  const Judged& j = judged("no_near_clip.json");
  for (std::uint32_t c : j.ref.cap) ASSERT_EQ(c, 0u);
  for (ShadowMethod m : gl::kAllShadowMethods) {
    const CrackReport r = judge("no_near_clip.json", m);
    // What remains is rasterization: sides snapped to 1/256 pixel move their
    // edges across pixel centres that lie within that distance of the exact
    // shadow boundary.  Such a pixel always has a neighbour across the boundary.
    EXPECT_LE(r.wrong, 10u) << to_string(m);
    for (int y = 0; y < j.ref.height; ++y)
      for (int x = 0; x < j.ref.width; ++x)
        if (is_wrong(r.verdict[j.ref.index(x, y)])) {
          EXPECT_TRUE(on_shadow_boundary(j.ref, x, y)) << to_string(m) << " pixel " << x << " " << y;
        }
  }
}

TEST(ShadowMethods, PublishedZPPlusCracksWhereTheNearCapDisagreesAndTheCorrectionRemovesThem) {
  // Figure 4's configuration: the near rectangle partly in shadow, ~1,800
  // case-B quads crossing it.
  const Judged& j = judged("near_cap_bunny_wall.json");
  const gl::ShadowFrame frame = gl::render_shadow_frame(j.scene, 0, ShadowMethod::ZPPlus);
  EXPECT_GT(frame.float_cases[static_cast<std::size_t>(QuadCase::B)], 1000u);
  const CrackReport published = judge_frame(frame, j.ref);
  ASSERT_TRUE(published.cap_mismatch.has_value());
  EXPECT_GT(published.wrong, 0u) << "section 5's artifacts";
  // Every crack of the published method lies on the exact near-cap's
  // boundary (a 4-neighbour has another exact cap count): where the cap pass
  // (projected through P_l) and the clipped sides (cut by the clipper) meet
  // and round differently.  Sometimes the cap pass is the one off the exact
  // boundary (cap_wrong), sometimes the clipped side.
  std::size_t cap_side = 0;
  for (int y = 0; y < j.ref.height; ++y)
    for (int x = 0; x < j.ref.width; ++x) {
      const std::size_t p = j.ref.index(x, y);
      if (!is_wrong(published.verdict[p])) continue;
      bool boundary = false;
      for (auto [dx, dy] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
        const int u = x + dx, v = y + dy;
        if (u >= 0 && v >= 0 && u < j.ref.width && v < j.ref.height && j.ref.cap[j.ref.index(u, v)] != j.ref.cap[p])
          boundary = true;
      }
      EXPECT_TRUE(boundary) << "pixel " << x << " " << y;
      cap_side += published.cap_wrong[p];
    }
  EXPECT_GT(cap_side, 0u) << "some cracks come from the cap pass itself";

  const CrackReport corrected = judge("near_cap_bunny_wall.json", ShadowMethod::ZPPlusCorrected);
  EXPECT_EQ(corrected.wrong, 0u);
  EXPECT_EQ(corrected.count_mismatch, 0u);
  // The correction leaves the near-cap pass as it is (section 5): the same
  // cap pixels still differ from the exact cap, and the sides follow them.
  EXPECT_EQ(corrected.cap_mismatch, published.cap_mismatch);
}

TEST(ShadowMethods, CaseDSwitchesThatOccluderToZFail) {
  const Judged& j = judged("case_d.json");
  const gl::ShadowFrame frame = gl::render_shadow_frame(j.scene, 0, ShadowMethod::ZPPlusCorrected);
  EXPECT_GT(frame.float_cases[static_cast<std::size_t>(QuadCase::D)], 0u);
  EXPECT_EQ(frame.zfail_objects, std::vector<std::size_t>{0});
  const CrackReport zfail = judge("case_d.json", ShadowMethod::ZFail);
  EXPECT_LE(zfail.wrong, 1u);

  // Far-only clamp (AMD_depth_clamp_separate): as right as Z-fail.
  gl::EmulationSettings far_only;
  far_only.switch_clamp = gl::SwitchClamp::DepthClampFar;
  EXPECT_LE(judge("case_d.json", ShadowMethod::ZPPlusCorrected, far_only).wrong, zfail.wrong);

  // The paper's NV_depth_clamp also disables near clipping: the box's lit
  // faces that cross the near plane are clipped at w_min instead of the near
  // plane, their light-cap depths differ from the depth pre-pass's, and the
  // LESS test turns ties into counts: wrong-shadowed pixels on the box only.
  gl::EmulationSettings both;
  both.switch_clamp = gl::SwitchClamp::DepthClamp;
  const CrackReport clamped = judge("case_d.json", ShadowMethod::ZPPlusCorrected, both);
  EXPECT_GT(clamped.wrong_shadowed, 1000u);
  for (std::size_t p = 0; p < clamped.verdict.size(); ++p)
    if (is_wrong(clamped.verdict[p])) {
      EXPECT_EQ(j.ref.object[p], 0) << "pixel index " << p;
    }
}

TEST(ShadowMethods, LightOnTheNearPlaneFallsBackToZFail) {
  const Judged& j = judged("light_on_near_plane.json");
  gl::EmulationSettings s;
  s.switch_clamp = gl::SwitchClamp::DepthClampFar;
  s.zfail_far = gl::ZFailFar::DepthClampFar;
  const gl::ShadowFrame zfail = gl::render_shadow_frame(j.scene, 0, ShadowMethod::ZFail, s);
  for (ShadowMethod m : {ShadowMethod::ZPPlus, ShadowMethod::ZPPlusCorrected}) {
    const gl::ShadowFrame f = gl::render_shadow_frame(j.scene, 0, m, s);
    EXPECT_FALSE(f.light_frustum.defined);
    EXPECT_NE(f.fallback.find("near plane"), std::string::npos) << f.fallback;
    EXPECT_TRUE(f.near_cap.empty());
    EXPECT_EQ(f.stencil, zfail.stencil) << to_string(m);
  }
  EXPECT_LE(judge_frame(zfail, j.ref).wrong, 1u);
}

TEST(ShadowMethods, PreloadCountsWhatZFailCounts) {
  // Preload adds every fragment once (front -1, back +1) and the depth-pass
  // ones again with the opposite sign: what is left is Z-fail's count, bit for
  // bit, in the same (infinite-far) pipeline.
  for (const char* name : {"near_split.json", "case_d.json", "eye_in_shadow.json", "default.json"}) {
    const Judged& j = judged(name);
    EXPECT_EQ(gl::render_shadow_frame(j.scene, 0, ShadowMethod::Preload).stencil,
              gl::render_shadow_frame(j.scene, 0, ShadowMethod::ZFail).stencil)
        << name;
  }
}

// A batch shares the depth pre-pass, silhouettes and geometry between
// methods; every frame is still exactly the one rendered alone, in any order
// of methods and with either far-plane mode.
TEST(ShadowMethods, ABatchRendersWhatEachMethodRendersAlone) {
  for (const char* name : {"case_d.json", "near_cap_bunny_wall.json", "eye_in_shadow.json"}) {
    const Judged& j = judged(name);
    for (gl::ZFailFar far : {gl::ZFailFar::Infinite, gl::ZFailFar::DepthClampFar}) {
      gl::EmulationSettings settings;
      settings.zfail_far = far;
      gl::ShadowFrameBatch batch(j.scene, 0, settings);
      for (ShadowMethod m : {ShadowMethod::Preload, ShadowMethod::ZPPlusCorrected, ShadowMethod::ZFail,
                             ShadowMethod::ZPass, ShadowMethod::ZPPlus}) {
        const gl::ShadowFrame shared = batch.render(m), alone = gl::render_shadow_frame(j.scene, 0, m, settings);
        const std::string what = std::string(name) + " " + std::string(to_string(m));
        EXPECT_EQ(shared.stencil, alone.stencil) << what;
        EXPECT_EQ(shared.object, alone.object) << what;
        EXPECT_EQ(shared.near_cap, alone.near_cap) << what;
        EXPECT_EQ(shared.float_cases, alone.float_cases) << what;
        EXPECT_EQ(shared.zfail_objects, alone.zfail_objects) << what;
        EXPECT_EQ(shared.fallback, alone.fallback) << what;
        EXPECT_EQ(shared.depth_pass.fragments, alone.depth_pass.fragments) << what;
        EXPECT_EQ(shared.depth_pass.depth_passed, alone.depth_pass.depth_passed) << what;
        EXPECT_EQ(shared.volume_pass.fragments, alone.volume_pass.fragments) << what;
        EXPECT_EQ(shared.cap_pass.fragments, alone.cap_pass.fragments) << what;
      }
    }
  }
}

TEST(ShadowMethods, NamesRoundTrip) {
  for (ShadowMethod m : gl::kAllShadowMethods) EXPECT_EQ(gl::shadow_method_from_string(to_string(m)), m);
  EXPECT_FALSE(gl::shadow_method_from_string("zpass+").has_value());
}

// l_near = l_far d / d_max compares two lengths, so both must be measured in
// one space: a view with a scale or a shear changes camera-space lengths.  A
// small box 0.0125 from the light, whose light pyramid is long and thin
// (reported: with d in world space and d_max in camera space, a view scaled by
// 1/2 put l_near beyond the box, and ZP+ lost it from the near-cap: 16 wrong
// pixels).  The same scene under a scaled view, halved lengths under the
// identity, a shear and an enlarging view: ZP+ is exact on all of them.
Scene small_box_scene(const std::string& view, double length) {
  const std::string l = std::to_string(length);
  const std::string text = R"({"camera":{"view":)" + view +
                           R"(,"frustum":{"left":-0.5,"right":0.5,"bottom":-0.5,"top":0.5,"near":1,"far":100},
      "width":64,"height":64},"lights":[{"position":[0,0,)" +
                           std::to_string(2 * length) + R"(]}],"objects":[{"mesh":"box.off","translate":[0,0,)" + l +
                           R"(],"scale":)" + std::to_string(0.025 * length) +
                           R"(},{"mesh":"box.off","translate":[0,0,)" + std::to_string(-20 * length) + R"(],"scale":)" +
                           std::to_string(8 * length) + R"(,"occluder":false}]})";
  return parse_scene(text, "small_box(" + view + ")", std::string(NEARCAP_SOURCE_DIR) + "/data/meshes");
}

TEST(ShadowMethods, LightNearPlaneIsMeasuredInOneSpaceUnderScaledAndShearedViews) {
  const std::string identity = "[[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]";
  const Scene halved = small_box_scene(identity, 1.0);
  const Scene scaled = small_box_scene("[[0.5,0,0,0],[0,0.5,0,0],[0,0,0.5,0],[0,0,0,1]]", 2.0);
  const Scene enlarged = small_box_scene("[[4,0,0,0],[0,4,0,0],[0,0,4,0],[0,0,0,1]]", 0.25);
  const Scene sheared = small_box_scene("[[1,0.3,0,0],[0,1,0.2,0],[0,0,1,0],[0,0,0,1]]", 1.0);
  const gl::LightFrustum a = gl::light_frustum(halved, 0, {}), b = gl::light_frustum(scaled, 0, {});
  ASSERT_TRUE(a.defined && b.defined);
  // The views differ by powers of two, exact scalings: only rounding in
  // another order may separate the two, by a few ulps.
  EXPECT_DOUBLE_EQ(b.d, a.d) << "d in camera space, like d_max";
  EXPECT_FLOAT_EQ(b.l_near, a.l_near);
  for (const Scene* scene : {&halved, &scaled, &enlarged, &sheared}) {
    const CameraSpaceScene cs(*scene);
    const PixelReference ref = compute_pixel_reference(cs, 0);
    const gl::LightFrustum lf = gl::light_frustum(*scene, 0, {});
    EXPECT_LT(lf.l_near, lf.l_far * lf.d / lf.d_max * 1.0001f) << scene->source;
    for (ShadowMethod m : {ShadowMethod::ZPPlus, ShadowMethod::ZPPlusCorrected}) {
      const CrackReport r = judge_frame(gl::render_shadow_frame(*scene, 0, m), ref);
      EXPECT_EQ(r.wrong, 0u) << scene->source << " " << to_string(m);
      ASSERT_TRUE(r.cap_mismatch.has_value());
      EXPECT_EQ(*r.cap_mismatch, 0u) << scene->source << " " << to_string(m);
    }
    // The configuration matters: Z-pass is wrong here (the near plane cuts the volume).
    EXPECT_GT(judge_frame(gl::render_shadow_frame(*scene, 0, ShadowMethod::ZPass), ref).wrong, 0u) << scene->source;
  }
}

// The box over the ground at `scale` (every length: camera, light, meshes).
Scene box_over_ground_at(double scale) {
  const std::string meshes = std::string(NEARCAP_SOURCE_DIR) + "/data/meshes/";
  const auto at = [scale](double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.17g", v * scale);  // the double itself, read back exactly
    return std::string(text);
  };
  const std::string text = R"({"camera": {"eye": [)" + at(0.7) + "," + at(0.5) + "," + at(0.5) + R"(], "target": [)" +
                           at(0.4) + ",0," + at(-3) + R"(], "up": [0, 1, 0], "fovy_deg": 60, "near": )" + at(0.1) +
                           R"(, "far": )" + at(100) + R"(, "width": 64, "height": 48}, "lights": [{"position": [0, )" +
                           at(5) + R"(, 0]}], "objects": [{"mesh": ")" + meshes +
                           R"(ground.off", "occluder": false, "scale": )" + at(1) + R"(}, {"mesh": ")" + meshes +
                           R"(box.off", "translate": [0, )" + at(2) + R"(, 0], "scale": )" + at(1) + "}]}";
  return parse_scene(text, "box over the ground at scale " + at(1), ".");
}

// The depth clamp's plane w >= w_min (DrawState::clamp_w_min) follows the
// near plane: a scene scaled by a power of two, down to a millionth of a
// unit and up to a million, draws the same stencil in every method, the
// depth-clamped draws (ZP+ corrected's switch to Z-fail, AtomicZP's sides,
// Z-fail with a clamped far plane) included.
TEST(ShadowMethods, AScaleByAPowerOfTwoDrawsTheSameStencil) {
  const Scene unit = box_over_ground_at(1);
  gl::EmulationSettings clamped;
  clamped.zfail_far = gl::ZFailFar::DepthClamp;
  const std::pair<ShadowMethod, gl::EmulationSettings> methods[] = {
      {ShadowMethod::ZPass, {}},   {ShadowMethod::ZFail, {}},           {ShadowMethod::ZFail, clamped},
      {ShadowMethod::ZPPlus, {}},  {ShadowMethod::ZPPlusCorrected, {}}, {ShadowMethod::Preload, {}},
      {ShadowMethod::AtomicZP, {}}};
  for (const double scale : {std::ldexp(1.0, -24), std::ldexp(1.0, 20)}) {
    const Scene scaled = box_over_ground_at(scale);
    for (const auto& [method, settings] : methods) {
      const gl::ShadowFrame a = gl::render_shadow_frame(unit, 0, method, settings);
      const gl::ShadowFrame b = gl::render_shadow_frame(scaled, 0, method, settings);
      EXPECT_EQ(a.stencil, b.stencil) << to_string(method) << " at scale " << scale;
      EXPECT_EQ(a.object, b.object) << to_string(method) << " at scale " << scale;
    }
  }
}

// A light a million and ten million units away (the sun's stand-in) over
// the tutorial's box and floor: Z-pass and Z-fail right, none refused (the
// sides' vertices extruded towards it are cut without cancellation:
// Clipping.AVertexExtrudedTowardsAFarLightDoesNotCancelTheCut).
TEST(ShadowMethods, AFarLightIsDrawnRight) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("nearcap_far_light_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "floor.off") << "OFF\n4 2 0\n-10 0 -10\n-10 0 10\n10 0 10\n10 0 -10\n3 0 1 2\n3 0 2 3\n";
  for (const char* light : {"[1e6, 5e6, 2e6]", "[1e7, 5e7, 2e7]"}) {
    const std::string text =
        R"({"camera": {"eye": [0.9, 0.51, 0.5], "target": [0.4, 0, -3], "up": [0, 1, 0], "fovy_deg": 60,
            "near": 0.1, "far": 100, "width": 64, "height": 48}, "lights": [{"position": )" +
        std::string(light) + R"(}], "objects": [{"mesh": "floor.off", "occluder": false}, {"mesh": ")" +
        std::string(NEARCAP_SOURCE_DIR) + R"(/data/meshes/box.off", "translate": [0, 2, 0]}]})";
    const Scene scene = parse_scene(text, "far light", dir.string());
    const CameraSpaceScene cs(scene);
    const PixelReference ref = compute_pixel_reference(cs, 0);
    for (ShadowMethod m : {ShadowMethod::ZPass, ShadowMethod::ZFail, ShadowMethod::AtomicZP}) {
      const CrackReport r = judge_frame(gl::render_shadow_frame(scene, 0, m), ref);
      EXPECT_EQ(r.wrong, 0u) << to_string(m) << ", light at " << light;
    }
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace nearcap
