// PGM and PNG encoders.
#include "nearcap/io/image_io.hpp"

#include <stb_image_write.h>

#include <cctype>

#include "nearcap/check.hpp"
#include "nearcap/error.hpp"

namespace nearcap {

std::string encode_pgm16(int width, int height, const std::vector<std::uint16_t>& pixels) {
  NEARCAP_CHECK(width > 0 && height > 0 && pixels.size() == static_cast<std::size_t>(width) * height);
  std::string out = "P5\n" + std::to_string(width) + " " + std::to_string(height) + "\n65535\n";
  out.reserve(out.size() + 2 * pixels.size());
  for (const std::uint16_t v : pixels) {
    out.push_back(static_cast<char>(v >> 8));
    out.push_back(static_cast<char>(v & 0xff));
  }
  return out;
}

std::vector<std::uint16_t> decode_pgm16(const std::string& bytes, const std::string& source, int* width, int* height) {
  std::size_t pos = 0;
  auto fail = [&](const std::string& what) { throw Error(ErrorKind::Parse, source + ": not a 16-bit PGM: " + what); };
  auto token = [&]() {
    while (pos < bytes.size()) {
      if (bytes[pos] == '#') {
        // A comment runs to the next line feed or carriage return (Netpbm's rule).
        while (pos < bytes.size() && bytes[pos] != '\n' && bytes[pos] != '\r') ++pos;
      } else if (std::isspace(static_cast<unsigned char>(bytes[pos]))) {
        ++pos;
      } else {
        break;
      }
    }
    const std::size_t start = pos;
    while (pos < bytes.size() && !std::isspace(static_cast<unsigned char>(bytes[pos]))) ++pos;
    return bytes.substr(start, pos - start);
  };
  if (token() != "P5") fail("magic is not P5");
  long long w = 0, h = 0, maxval = 0;
  try {
    w = std::stoll(token());
    h = std::stoll(token());
    maxval = std::stoll(token());
  } catch (const std::exception&) {
    fail("malformed header");
  }
  if (w <= 0 || h <= 0 || w > 65536 || h > 65536) fail("bad size");
  if (maxval != 65535) fail("maxval is not 65535");
  ++pos;  // the single whitespace after maxval
  const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  if (bytes.size() < pos + 2 * n) fail("truncated pixel data");
  std::vector<std::uint16_t> pixels(n);
  for (std::size_t k = 0; k < n; ++k)
    pixels[k] = static_cast<std::uint16_t>((static_cast<unsigned char>(bytes[pos + 2 * k]) << 8) |
                                           static_cast<unsigned char>(bytes[pos + 2 * k + 1]));
  *width = static_cast<int>(w);
  *height = static_cast<int>(h);
  return pixels;
}

std::string encode_png_rgb(int width, int height, const std::vector<std::uint8_t>& rgb) {
  NEARCAP_CHECK(width > 0 && height > 0 && rgb.size() == 3 * static_cast<std::size_t>(width) * height);
  std::string out;
  auto sink = [](void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data), static_cast<std::size_t>(size));
  };
  if (!stbi_write_png_to_func(sink, &out, width, height, 3, rgb.data(), width * 3))
    throw Error(ErrorKind::Io, "PNG encoding failed");
  return out;
}

std::string png_with_text(const std::string& png, const std::string& keyword, const std::string& text) {
  // Signature (8 bytes), then IHDR: length (4), type (4), 13 data bytes, CRC (4).
  constexpr std::size_t kAfterHeader = 8 + 4 + 4 + 13 + 4;
  NEARCAP_CHECK(png.size() > kAfterHeader && png.compare(12, 4, "IHDR") == 0);
  NEARCAP_CHECK(!keyword.empty() && keyword.size() < 80 && keyword.find('\0') == std::string::npos);
  const std::string data = "tEXt" + keyword + std::string(1, '\0') + text;
  // The chunk's CRC-32 (ISO 3309, as PNG specifies) over its type and data.
  std::uint32_t crc = 0xffffffffu;
  for (const char c : data) {
    crc ^= static_cast<unsigned char>(c);
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xedb88320u & (0u - (crc & 1u)));
  }
  crc ^= 0xffffffffu;
  auto be32 = [](std::uint32_t v) {
    return std::string{static_cast<char>(v >> 24), static_cast<char>(v >> 16), static_cast<char>(v >> 8),
                       static_cast<char>(v)};
  };
  return png.substr(0, kAfterHeader) + be32(static_cast<std::uint32_t>(data.size() - 4)) + data + be32(crc) +
         png.substr(kAfterHeader);
}

}  // namespace nearcap
