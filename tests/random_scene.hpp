// Random scenes for property tests: boxes between a point light and a camera
// that looks down -z, over a large receiver slab, all with dyadic numbers so
// that a translation by a dyadic offset is exact (see README, exactness).
#pragma once

#include <rapidcheck.h>
#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

#include "nearcap/error.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/scene/scene.hpp"

namespace nearcap::test {

// The unit cube [-1/2, 1/2]^3, closed and outward.
inline std::string unit_box_path() { return std::string(NEARCAP_SOURCE_DIR) + "/data/bad/box.off"; }

struct RandomSceneParams {
  std::vector<std::array<int, 3>> box_centres16;  // sixteenths
  std::vector<int> box_scales16;
  std::vector<std::array<int, 3>> box_rotations_deg;
  std::array<int, 3> light16;
  std::array<int, 3> eye16;
  int near64 = 8;
  int half_width64 = 16;
  int width = 16, height = 12;
};

inline rc::Gen<RandomSceneParams> random_scene_params() {
  return rc::gen::exec([] {
    RandomSceneParams p;
    const int boxes = *rc::gen::inRange(1, 4);
    for (int b = 0; b < boxes; ++b) {
      p.box_centres16.push_back({*rc::gen::inRange(-20, 21), *rc::gen::inRange(-4, 28), *rc::gen::inRange(-56, 4)});
      p.box_scales16.push_back(*rc::gen::inRange(4, 20));
      p.box_rotations_deg.push_back({*rc::gen::inRange(0, 90), *rc::gen::inRange(0, 90), *rc::gen::inRange(0, 90)});
    }
    p.light16 = {*rc::gen::inRange(-40, 41), *rc::gen::inRange(40, 96), *rc::gen::inRange(-64, 16)};
    p.eye16 = {*rc::gen::inRange(-8, 9), *rc::gen::inRange(-8, 9), *rc::gen::inRange(8, 24)};
    if (*rc::gen::inRange(0, 2) == 0) {
      // Half of the scenes put a box on the segment from the eye to the light:
      // the eye then sits in a shadow volume, the case Z-pass gets wrong.
      const int f = *rc::gen::inRange(4, 12);  // sixteenths of the way
      for (int k = 0; k < 3; ++k) p.box_centres16[0][k] = p.eye16[k] + (p.light16[k] - p.eye16[k]) * f / 16;
    }
    p.near64 = *rc::gen::inRange(2, 32);
    p.half_width64 = *rc::gen::inRange(4, 32);
    return p;
  });
}

// The scene as JSON text, everything shifted by offset16 / 16.
inline std::string random_scene_json(const RandomSceneParams& p, const std::array<int, 3>& offset16 = {0, 0, 0}) {
  auto v16 = [&](const std::array<int, 3>& a) {
    return nlohmann::json::array(
        {(a[0] + offset16[0]) / 16.0, (a[1] + offset16[1]) / 16.0, (a[2] + offset16[2]) / 16.0});
  };
  nlohmann::json j;
  const auto e = v16(p.eye16);
  const double near = p.near64 / 64.0, hw = p.half_width64 / 64.0;
  j["camera"] = {
      {"view",
       {{1, 0, 0, -e[0].get<double>()}, {0, 1, 0, -e[1].get<double>()}, {0, 0, 1, -e[2].get<double>()}, {0, 0, 0, 1}}},
      {"frustum",
       {{"left", -hw}, {"right", hw}, {"bottom", -hw * 0.75}, {"top", hw * 0.75}, {"near", near}, {"far", 64}}},
      {"width", p.width},
      {"height", p.height}};
  j["lights"] = nlohmann::json::array({{{"position", v16(p.light16)}}});
  j["objects"] = nlohmann::json::array();
  for (std::size_t b = 0; b < p.box_centres16.size(); ++b)
    j["objects"].push_back({{"mesh", unit_box_path()},
                            {"translate", v16(p.box_centres16[b])},
                            {"scale", p.box_scales16[b] / 16.0},
                            {"rotate_deg", p.box_rotations_deg[b]}});
  j["objects"].push_back(
      {{"mesh", unit_box_path()}, {"translate", v16({0, -8 * 16 - 24, 0})}, {"scale", 16}, {"occluder", false}});
  return j.dump();
}

// The scene, or nothing when it is rejected (e.g. a light inside a box).
inline std::optional<Scene> try_parse_scene(const std::string& json) {
  try {
    return parse_scene(json, "random", ".");
  } catch (const Error&) {
    return std::nullopt;
  }
}

// An exactly representable offset, in sixteenths, of at most `limit` units.
inline rc::Gen<std::array<int, 3>> dyadic_offset16(int limit) {
  return rc::gen::exec([limit] {
    return std::array<int, 3>{*rc::gen::inRange(-limit * 16, limit * 16), *rc::gen::inRange(-limit * 16, limit * 16),
                              *rc::gen::inRange(-limit * 16, limit * 16)};
  });
}

}  // namespace nearcap::test
