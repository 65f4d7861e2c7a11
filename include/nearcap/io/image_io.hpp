// nearcap/io/image_io.hpp — image encoders, to bytes in memory (the caller writes
// them atomically).  Rows are given TOP row first, as both formats store them.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace nearcap {

// Binary 16-bit PGM (P5, maxval 65535, big-endian samples).
std::string encode_pgm16(int width, int height, const std::vector<std::uint16_t>& top_row_first);

// Reads back what encode_pgm16 writes (P5, maxval 65535); throws Error(Parse).
std::vector<std::uint16_t> decode_pgm16(const std::string& bytes, const std::string& source, int* width, int* height);

// 8-bit RGB PNG (stb_image_write).
std::string encode_png_rgb(int width, int height, const std::vector<std::uint8_t>& rgb_top_row_first);

// The PNG `png` with a tEXt chunk (keyword, text: Latin-1, keyword 1 to 79
// characters) right after its header, so that a viewer or a test reads what
// the picture says ("Title": its legend's title line).
std::string png_with_text(const std::string& png, const std::string& keyword, const std::string& text);

}  // namespace nearcap
