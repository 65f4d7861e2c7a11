// libFuzzer target: the whole pipeline behind one scene file.  The scene is
// read and validated (meshes resolved against fuzz/meshes), its viewport is
// shrunk to at most 8 x 6 pixels so that an execution stays cheap, and then
// every light goes through what the commands do: the classification (exact
// and engine), the exact near-cap arrangement, the per-pixel reference, and
// every float method judged against it.  Any nearcap::Error is an accepted
// answer; anything else (a crash, an internal check, a sanitizer report,
// another exception) is a bug.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>

#include "nearcap/error.hpp"
#include "nearcap/exact/classification.hpp"
#include "nearcap/exact/near_cap.hpp"
#include "nearcap/gl/shadow_methods.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/judge/case_comparison.hpp"
#include "nearcap/judge/crack_map.hpp"
#include "nearcap/scene/scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > 16 * 1024) return 0;  // bounded input size
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    nearcap::Scene scene = nearcap::parse_scene(text, "fuzz.json", NEARCAP_FUZZ_MESH_DIR);
    scene.camera.width = std::min(scene.camera.width, 8);
    scene.camera.height = std::min(scene.camera.height, 6);
    const nearcap::CameraSpaceScene cs(scene);
    (void)nearcap::compare_engine_cases(cs, nearcap::classify_scene(cs));
    const std::size_t lights = std::min<std::size_t>(scene.lights.size(), 2);
    for (std::size_t light = 0; light < lights; ++light) {
      try {
        (void)nearcap::NearCap::build(cs, light);
      } catch (const nearcap::Error&) {  // a light in the near plane: no near-cap
      }
      const nearcap::PixelReference ref = nearcap::compute_pixel_reference(cs, light);
      for (nearcap::gl::ShadowMethod m : nearcap::gl::kAllShadowMethods)
        (void)nearcap::judge_frame(nearcap::gl::render_shadow_frame(scene, light, m), ref);
      // ZP+ with the near-cap built from its clipped sides (its loops, their
      // shortcuts and the exact windings), on both projections.
      nearcap::gl::EmulationSettings sides;
      sides.light_frustum.projection = nearcap::gl::LightProjection::ClippedSides;
      for (nearcap::gl::ZPassFar far : {nearcap::gl::ZPassFar::Finite, nearcap::gl::ZPassFar::Infinite}) {
        sides.zpass_far = far;
        (void)nearcap::judge_frame(
            nearcap::gl::render_shadow_frame(scene, light, nearcap::gl::ShadowMethod::ZPPlus, sides), ref);
      }
      // Reversed-Z (the reversed depth mapping, a float depth buffer): every
      // method, the clipped-sides cap included.
      nearcap::gl::EmulationSettings reversed;
      reversed.depth = nearcap::gl::DepthFormat::Float32;
      reversed.depth_mapping = nearcap::gl::DepthMapping::Reversed;
      for (nearcap::gl::ShadowMethod m : nearcap::gl::kAllShadowMethods)
        (void)nearcap::judge_frame(nearcap::gl::render_shadow_frame(scene, light, m, reversed), ref);
      sides.depth = reversed.depth;
      sides.depth_mapping = reversed.depth_mapping;
      (void)nearcap::judge_frame(
          nearcap::gl::render_shadow_frame(scene, light, nearcap::gl::ShadowMethod::ZPPlus, sides), ref);
      nearcap::gl::EmulationSettings model;
      model.raster = nearcap::gl::llvmpipe_model();
      for (nearcap::gl::ShadowMethod m : nearcap::gl::kAllShadowMethods)
        (void)nearcap::judge_frame(nearcap::gl::render_shadow_frame(scene, light, m, model), ref);
    }
  } catch (const nearcap::Error&) {
  }
  return 0;
}
