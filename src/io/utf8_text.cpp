// Well-formed UTF-8 (see utf8_text.hpp).
#include "nearcap/io/utf8_text.hpp"

#include <cstdint>
#include <cstdio>

namespace nearcap::io {

std::size_t first_non_utf8(const std::string& s) {
  std::size_t k = 0;
  while (k < s.size()) {
    const auto lead = static_cast<unsigned char>(s[k]);
    if (lead < 0x80) {
      ++k;
      continue;
    }
    std::size_t more = 0;
    std::uint32_t code = 0, least = 0;
    if ((lead & 0xE0) == 0xC0) {
      more = 1, code = lead & 0x1Fu, least = 0x80;
    } else if ((lead & 0xF0) == 0xE0) {
      more = 2, code = lead & 0x0Fu, least = 0x800;
    } else if ((lead & 0xF8) == 0xF0) {
      more = 3, code = lead & 0x07u, least = 0x10000;
    } else {
      return k;
    }
    for (std::size_t i = 1; i <= more; ++i) {
      if (k + i >= s.size()) return k;
      const auto next = static_cast<unsigned char>(s[k + i]);
      if ((next & 0xC0) != 0x80) return k;
      code = (code << 6) | (next & 0x3Fu);
    }
    if (code < least || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF)) return k;
    k += more + 1;
  }
  return std::string::npos;
}

std::size_t first_control_character(const std::string& s) {
  for (std::size_t k = 0; k < s.size(); ++k) {
    const auto byte = static_cast<unsigned char>(s[k]);
    if (byte < 0x20 || byte == 0x7f) return k;
  }
  return std::string::npos;
}

std::string escaped_control_characters(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  for (const char c : s) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte >= 0x20 && byte != 0x7f) {
      out += c;
    } else if (c == '\n' || c == '\r' || c == '\t') {
      out += c == '\n' ? "\\n" : c == '\r' ? "\\r" : "\\t";
    } else {
      char escape[5];
      std::snprintf(escape, sizeof escape, "\\x%02x", byte);
      out += escape;
    }
  }
  return out;
}

}  // namespace nearcap::io
