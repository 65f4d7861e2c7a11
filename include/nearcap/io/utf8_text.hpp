// nearcap/io/utf8_text.hpp — whether text is well-formed UTF-8: what a CSV
// field, a JSON string or a message may hold where a file name is bytes.
#pragma once

#include <cstddef>
#include <string>

namespace nearcap::io {

// The offset of the first byte of `s` that does not belong to a well-formed
// UTF-8 sequence (overlong forms, surrogates and code points past U+10FFFF
// included), or npos.
std::size_t first_non_utf8(const std::string& s);

// The offset of the first control character of `s` (below U+0020, or DEL),
// or npos.
std::size_t first_control_character(const std::string& s);

}  // namespace nearcap::io
