// libFuzzer target: the 16-bit PGM reader (reference images read back by
// tests and, later, by the crack analysis).  Any input must decode or throw
// nearcap::Error; a decoded image must re-encode to a file that decodes to the
// same pixels.
#include <cstdint>
#include <cstdlib>
#include <string>

#include "nearcap/error.hpp"
#include "nearcap/io/image_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > 1 << 20) return 0;  // bounded input size
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  try {
    int w = 0, h = 0;
    const std::vector<std::uint16_t> pixels = nearcap::decode_pgm16(bytes, "fuzz.pgm", &w, &h);
    int w2 = 0, h2 = 0;
    if (nearcap::decode_pgm16(nearcap::encode_pgm16(w, h, pixels), "round trip", &w2, &h2) != pixels || w2 != w ||
        h2 != h)
      std::abort();
  } catch (const nearcap::Error&) {
  }
  return 0;
}
