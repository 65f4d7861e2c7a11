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

// The offset of the first control character of `s` (C0: below U+0020; DEL;
// C1: U+0080 to U+009F, well-formed UTF-8), or npos.
std::size_t first_control_character(const std::string& s);

// `s` with each control character written as an escape (\n, \r, \t, \xHH
// for the other C0 and DEL, \u00HH for C1) and each byte outside well-formed
// UTF-8 as \xHH.  What an error line or a CSV field shows of text that may
// come from a file name, so that it stays one line of UTF-8 a terminal shows
// as text.
std::string escaped_control_characters(const std::string& s);

}  // namespace nearcap::io
