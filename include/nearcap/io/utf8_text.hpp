// nearcap/io/utf8_text.hpp — what text a CSV field, a JSON string or a
// one-line message may hold where a file name is bytes: well-formed UTF-8,
// control characters written as escapes.
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

// `s` with each control character written as an escape: \n, \r, \t or
// \xHH.  What an error line or a CSV field shows of text that may come from
// a file name, so that it stays on one line.
std::string escaped_control_characters(const std::string& s);

}  // namespace nearcap::io
