// Light facing: the object-space fast path (precomputed face planes, the light
// moved into object space) must give exactly the camera-space predicate's
// answer on every triangle; and mirrored objects keep their outer side.
#include <gtest/gtest.h>

#include "nearcap/exact/light_facing.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/scene/scene.hpp"
#include "random_scene.hpp"

namespace nearcap {
namespace {

Facing from_side(Sign s) {
  return s == Sign::Positive ? Facing::Front : (s == Sign::Negative ? Facing::Back : Facing::EdgeOn);
}

TEST(LightFacing, ObjectSpacePlanesAgreeWithCameraSpaceOnBundledScenes) {
  for (const char* name : {"bunny", "twisted", "default", "case_d", "exact_camera"}) {
    const Scene scene = load_scene(std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/" + name + ".json");
    const CameraSpaceScene cs(scene);
    for (std::size_t o = 0; o < cs.object_count(); ++o) {
      if (!scene.objects[o].occluder) continue;
      ASSERT_EQ(cs.mesh(o).face_planes.plane.size(), cs.mesh(o).triangles.size()) << "planes computed at load";
      const std::vector<Facing> fast = light_facing(cs, o, 0, nullptr);
      std::size_t front = 0;
      for (FaceIndex f = 0; f < fast.size(); ++f) {
        ASSERT_EQ(fast[f], from_side(light_side(cs, o, f, 0, nullptr))) << name << " face " << f;
        front += fast[f] == Facing::Front;
      }
      EXPECT_GT(front, 0u) << name;
      EXPECT_LT(front, fast.size()) << name;
    }
  }
}

TEST(LightFacing, MirroredObjectKeepsItsOuterSide) {
  // The unit box mirrored by a negative scale: the face towards the light is
  // still front-facing.
  for (double scale : {1.0, -1.0}) {
    nlohmann::json j;
    j["camera"] = {{"view", {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}}},
                   {"frustum", {{"left", -1}, {"right", 1}, {"bottom", -1}, {"top", 1}, {"near", 1}, {"far", 100}}},
                   {"width", 4},
                   {"height", 4}};
    j["lights"] = nlohmann::json::array({{{"position", {0, 5, -4}}}});
    j["objects"] =
        nlohmann::json::array({{{"mesh", test::unit_box_path()}, {"translate", {0, 0, -4}}, {"scale", scale}}});
    const Scene scene = parse_scene(j.dump(), "mirror", ".");
    const CameraSpaceScene cs(scene);
    const std::vector<Facing> facing = light_facing(cs, 0, 0, nullptr);
    std::size_t front = 0;
    for (FaceIndex f = 0; f < facing.size(); ++f) {
      if (facing[f] != Facing::Front) continue;
      ++front;
      // A front face of a box lit from straight above is on the top (y = +1/2).
      for (VertexIndex v : scene.objects[0].mesh->triangles[f])
        EXPECT_EQ(cs.vertex_estimate(0, v).y, 0.5) << "scale " << scale;
    }
    EXPECT_EQ(front, 2u) << "scale " << scale;
  }
}

}  // namespace
}  // namespace nearcap
