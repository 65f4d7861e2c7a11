// libFuzzer target: one mesh format reader as nearcap uses it (parse, then
// occluder validation), chosen at compile time by NEARCAP_FUZZ_FORMAT.
#include <cstddef>
#include <cstdint>
#include <string>

#include "nearcap/error.hpp"
#include "nearcap/io/mesh_file.hpp"
#include "nearcap/scene/mesh.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > 64 * 1024) return 0;  // bounded input size
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  try {
    nearcap::TriangleMesh mesh = nearcap::parse_mesh(bytes, NEARCAP_FUZZ_FORMAT, "fuzz." NEARCAP_FUZZ_FORMAT);
    if (mesh.triangles.size() <= 20000) nearcap::validate_occluder(mesh);
  } catch (const nearcap::Error&) {
  }
  return 0;
}
