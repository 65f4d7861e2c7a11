// tests/support/cached_reference_frames.hpp — what the exact reference's
// caches (exact/light_setup.hpp, exact/eye_setup.hpp) are checked with: a
// property case's frames, each one move away from the one before, parsed
// with one mesh cache as a sweep parses them; and the equalities a cached
// tracer must meet: the reference a fresh tracer gives, and brute force on
// every pixel.
#pragma once

#include <rapidcheck.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "nearcap/error.hpp"
#include "nearcap/exact/pixel_reference.hpp"
#include "nearcap/io/scene_file.hpp"

namespace nearcap::test {

inline bool same_reference(const PixelReference& a, const PixelReference& b) {
  return a.cap == b.cap && a.stencil == b.stencil && a.object == b.object && a.face == b.face &&
         a.cap_pixels_by_object == b.cap_pixels_by_object;
}

inline bool same_sample(const PixelSample& a, const PixelSample& b) {
  return a.cap == b.cap && a.stencil == b.stencil && a.object == b.object && a.face == b.face;
}

// A bundled scene (data/scenes/NAME.json) at a width x height viewport, its
// meshes from `meshes`.
inline Scene bundled_scene_at(const std::string& name, int width, int height, MeshCache& meshes) {
  const std::string dir = std::string(NEARCAP_SOURCE_DIR) + "/data/scenes";
  const std::string path = dir + "/" + name + ".json";
  std::ifstream in(path);
  nlohmann::json j = nlohmann::json::parse(in);
  j["camera"]["width"] = width;
  j["camera"]["height"] = height;
  return parse_scene(j.dump(), path, dir, &meshes);
}

// One frame of a property case: what moved, and its scene's JSON.
struct ReferenceFrame {
  const char* what;
  std::string json;
};

// The frames' scenes, one mesh object for every frame; a property case whose
// frame the scene reader rejects (a light moved inside a box) is discarded.
inline std::vector<Scene> parse_reference_frames(const std::vector<ReferenceFrame>& frames, MeshCache& meshes) {
  std::vector<Scene> scenes;
  for (const ReferenceFrame& f : frames) {
    try {
      scenes.push_back(parse_scene(f.json, f.what, ".", &meshes));
    } catch (const Error&) {
      RC_DISCARD("a frame's scene is rejected (a light inside a box)");
    }
  }
  return scenes;
}

// Inside a property: `cached` gives the reference `fresh` gives, and its
// grids find what brute force finds at every pixel.
inline void rc_assert_cached_equals_fresh(const PixelReferenceTracer& cached, const PixelReferenceTracer& fresh) {
  RC_ASSERT(same_reference(compute_pixel_reference(cached), compute_pixel_reference(fresh)));
  const Camera& camera = cached.scene().scene().camera;
  for (int j = 0; j < camera.height; ++j)
    for (int i = 0; i < camera.width; ++i)
      RC_ASSERT(same_sample(cached.trace(i, j, nullptr), cached.trace_brute_force(i, j, nullptr)));
}

}  // namespace nearcap::test
