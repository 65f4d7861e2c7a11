// libFuzzer target: the scene JSON reader with all its validation (schema,
// camera, transforms, meshes resolved against fuzz/meshes, light placement).
// Any nearcap::Error is an accepted answer; anything else (a crash, a sanitizer
// report, another exception) is a bug.
#include <cstddef>
#include <cstdint>
#include <string>

#include "nearcap/error.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/scene/scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > 64 * 1024) return 0;  // bounded input size
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const nearcap::Scene scene = nearcap::parse_scene(text, "fuzz.json", NEARCAP_FUZZ_MESH_DIR);
    (void)scene;
  } catch (const nearcap::Error&) {
  }
  return 0;
}
