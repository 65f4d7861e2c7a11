// Well-formed UTF-8 (see utf8_text.hpp).
#include "nearcap/io/utf8_text.hpp"

#include <cstdint>
#include <cstdio>

namespace nearcap::io {
namespace {

// The length of the well-formed UTF-8 sequence starting at s[k] (1 to 4), or
// 0 where s[k] starts none.
std::size_t sequence_length(const std::string& s, std::size_t k) {
  const auto lead = static_cast<unsigned char>(s[k]);
  if (lead < 0x80) return 1;
  std::size_t more = 0;
  std::uint32_t code = 0, least = 0;
  if ((lead & 0xE0) == 0xC0) {
    more = 1, code = lead & 0x1Fu, least = 0x80;
  } else if ((lead & 0xF0) == 0xE0) {
    more = 2, code = lead & 0x0Fu, least = 0x800;
  } else if ((lead & 0xF8) == 0xF0) {
    more = 3, code = lead & 0x07u, least = 0x10000;
  } else {
    return 0;
  }
  for (std::size_t i = 1; i <= more; ++i) {
    if (k + i >= s.size()) return 0;
    const auto next = static_cast<unsigned char>(s[k + i]);
    if ((next & 0xC0) != 0x80) return 0;
    code = (code << 6) | (next & 0x3Fu);
  }
  if (code < least || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF)) return 0;
  return more + 1;
}

// Whether the well-formed sequence of `length` bytes at s[k] is a control
// character: C0 (below U+0020), DEL (U+007F) or C1 (U+0080 to U+009F, whose
// UTF-8 form is 0xC2 0x80 to 0xC2 0x9F).
bool is_control(const std::string& s, std::size_t k, std::size_t length) {
  const auto lead = static_cast<unsigned char>(s[k]);
  if (length == 1) return lead < 0x20 || lead == 0x7f;
  return length == 2 && lead == 0xC2 && static_cast<unsigned char>(s[k + 1]) < 0xA0;
}

}  // namespace

std::size_t first_non_utf8(const std::string& s) {
  for (std::size_t k = 0; k < s.size();) {
    const std::size_t length = sequence_length(s, k);
    if (length == 0) return k;
    k += length;
  }
  return std::string::npos;
}

std::size_t first_control_character(const std::string& s) {
  for (std::size_t k = 0; k < s.size();) {
    const std::size_t length = sequence_length(s, k);
    if (length != 0 && is_control(s, k, length)) return k;
    k += length == 0 ? 1 : length;
  }
  return std::string::npos;
}

std::string escaped_control_characters(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  for (std::size_t k = 0; k < s.size();) {
    const std::size_t length = sequence_length(s, k);
    const auto byte = static_cast<unsigned char>(s[k]);
    char escape[8];
    if (length != 0 && !is_control(s, k, length)) {
      out.append(s, k, length);
    } else if (byte == '\n' || byte == '\r' || byte == '\t') {
      out += byte == '\n' ? "\\n" : byte == '\r' ? "\\r" : "\\t";
    } else if (length == 2) {  // C1: U+0080 to U+009F
      std::snprintf(escape, sizeof escape, "\\u%04x", static_cast<unsigned char>(s[k + 1]));
      out += escape;
    } else {  // another C0 character, DEL, or a byte outside UTF-8
      std::snprintf(escape, sizeof escape, "\\x%02x", byte);
      out += escape;
    }
    k += length == 0 ? 1 : length;
  }
  return out;
}

}  // namespace nearcap::io
