// Linked with src/raytrace/embree_unavailable.cpp (tests/CMakeLists.txt): a
// build without Embree.  Prints the error raytrace gives there; ctest matches
// the message.  Exit 0 only when it refused as documented.
#include <cstdio>
#include <string>

#include "nearcap/error.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/raytrace/shadow_ray_tracer.hpp"

int main() {
  if (nearcap::raytrace::raytrace_available()) return 1;
  const nearcap::Scene scene = nearcap::load_scene(std::string(NEARCAP_DATA_DIR) + "/scenes/default.json");
  try {
    nearcap::raytrace::raytrace_shadows(scene, 0);
  } catch (const nearcap::Error& e) {
    std::printf("error (%s): %s\n", std::string(nearcap::to_string(e.kind())).c_str(), e.what());
    return e.kind() == nearcap::ErrorKind::Unavailable ? 0 : 1;
  }
  return 1;
}
