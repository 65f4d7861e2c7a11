// The near-cap arrangement against the brute-force count: at every pixel
// centre inside a face the face's count is the count there; the faces tile the
// near rectangle; a light in the near plane is refused.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include "nearcap/error.hpp"
#include "nearcap/light_facing.hpp"
#include "nearcap/near_cap.hpp"
#include "nearcap/segment_crossing.hpp"
#include "random_scene.hpp"

namespace nearcap {
namespace {

RC_GTEST_PROP(NearCap, FacesCarryTheBruteForceCount, ()) {
  test::RandomSceneParams params = *test::random_scene_params();
  // A large near rectangle, so that silhouettes and near-plane cuts cross it.
  params.near64 = 4 * *rc::gen::inRange(4, 16);
  params.half_width64 = *rc::gen::inRange(16, 64);
  if (*rc::gen::inRange(0, 2) == 0) {
    // Half of the scenes centre a box on the near plane, in view: near-plane
    // cuts of front faces then bound the near-cap.
    params.box_centres16[0] = {params.eye16[0] + *rc::gen::inRange(-8, 9), params.eye16[1] + *rc::gen::inRange(-8, 9),
                               params.eye16[2] - params.near64 / 4};
  }
  params.width = 24;
  params.height = 18;
  Scene scene;
  try {
    scene = parse_scene(test::random_scene_json(params), "random", ".");
  } catch (const Error& e) {
    RC_DISCARD("scene rejected");
  }
  const CameraSpaceScene cs(scene);
  std::optional<NearCap> cap;
  try {
    cap = NearCap::build(cs, 0);
  } catch (const Error& e) {
    RC_ASSERT(e.kind() == ErrorKind::Degenerate);
    RC_DISCARD("light in the near plane");
  }
  std::vector<std::vector<Facing>> facing(cs.object_count());
  for (std::size_t o = 0; o < cs.object_count(); ++o)
    if (scene.objects[o].occluder) facing[o] = light_facing(cs, o, 0, nullptr);

  const Frustum& fr = scene.camera.frustum;
  double area = 0;
  for (const NearCapFace& f : cap->faces()) area += f.area_estimate;
  const double expected = (fr.right - fr.left) * (fr.top - fr.bottom);
  RC_ASSERT(std::fabs(area - expected) <= 1e-9 * expected);

  int located = 0;
  for (int j = 0; j < scene.camera.height; ++j)
    for (int i = 0; i < scene.camera.width; ++i) {
      const SamplePoint p = pixel_centre(fr, scene.camera.width, scene.camera.height, i, j);
      const std::optional<std::size_t> count = cap->count_at(p.exact.x, p.exact.y);
      if (!count) continue;  // on an edge: the perturbation, not the arrangement, decides
      ++located;
      RC_ASSERT(*count == near_cap_count_brute_force(cs, 0, facing, p, nullptr));
    }
  RC_ASSERT(located > 0);
  RC_CLASSIFY(cap->faces().size() > 1, "near-cap with several faces");
  RC_CLASSIFY(cap->max_count() > 0, "non-zero near-cap");
}

Scene scene_with_light(const std::array<double, 3>& light) {
  nlohmann::json j;
  j["camera"] = {{"view", {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}}},
                 {"frustum", {{"left", -1}, {"right", 1}, {"bottom", -1}, {"top", 1}, {"near", 1}, {"far", 100}}},
                 {"width", 8},
                 {"height", 8}};
  j["lights"] = nlohmann::json::array({{{"position", light}}});
  j["objects"] = nlohmann::json::array({{{"mesh", test::unit_box_path()}, {"translate", {0, 0, -1}}, {"scale", 1}}});
  return parse_scene(j.dump(), "box straddling the near plane", ".");
}

TEST(NearCap, LightInTheNearPlaneIsDegenerate) {
  const Scene scene = scene_with_light({3, 0, -1});
  const CameraSpaceScene cs(scene);
  try {
    NearCap::build(cs, 0);
    FAIL() << "expected Error(Degenerate)";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Degenerate);
    EXPECT_NE(std::string(e.what()).find("near plane"), std::string::npos) << e.what();
  }
}

// A unit box centred on the near plane (z in [-3/2, -1/2]), light at (0, 0, 3)
// behind the camera: the near plane cuts the box, the cut of its front faces
// (the face z = -1/2 is the only front face... which lies off the plane) and
// the projected silhouette bound one face of count 1 inside the rectangle.
TEST(NearCap, BoxCutByTheNearPlane) {
  const Scene scene = scene_with_light({0, 0, 3});
  const CameraSpaceScene cs(scene);
  const NearCap cap = NearCap::build(cs, 0);
  EXPECT_EQ(cap.max_count(), 1u);
  // The centre of the rectangle looks at the box through its front face.
  EXPECT_EQ(cap.count_at(Rational(1, 7), Rational(1, 9)).value_or(99), 1u);
  // A corner of the rectangle misses it.
  EXPECT_EQ(cap.count_at(Rational(-9, 10), Rational(9, 10)).value_or(99), 0u);
  // Off the rectangle: no face.
  EXPECT_FALSE(cap.count_at(Rational(2), Rational(0)).has_value());
}

}  // namespace
}  // namespace nearcap
