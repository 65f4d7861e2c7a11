// PLY (ascii, binary_little_endian, binary_big_endian), parsed by nearcap.
//
// The header declares elements and their typed properties; nearcap reads the
// "vertex" element's x, y, z and the "face" element's "vertex_indices" (or
// "vertex_index") list, and skips every other element and property by its
// declared type.  A coordinate keeps its declared precision: a `float`
// property is the float32 value, a `double` one the nearest double.
#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "mesh_reading.hpp"
#include "nearcap/error.hpp"
#include "nearcap/io/mesh_file.hpp"
#include "nearcap/scene/mesh.hpp"

namespace nearcap {
namespace {

using mesh_reading::fail;

enum class PlyType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };
enum class PlyFormat { Ascii, BinaryLittleEndian, BinaryBigEndian };

bool parse_ply_type(const std::string& name, PlyType& type) {
  static const std::pair<const char*, PlyType> kTypes[] = {
      {"char", PlyType::Int8},      {"int8", PlyType::Int8},       {"uchar", PlyType::UInt8},
      {"uint8", PlyType::UInt8},    {"short", PlyType::Int16},     {"int16", PlyType::Int16},
      {"ushort", PlyType::UInt16},  {"uint16", PlyType::UInt16},   {"int", PlyType::Int32},
      {"int32", PlyType::Int32},    {"uint", PlyType::UInt32},     {"uint32", PlyType::UInt32},
      {"float", PlyType::Float32},  {"float32", PlyType::Float32}, {"double", PlyType::Float64},
      {"float64", PlyType::Float64}};
  for (const auto& [n, t] : kTypes) {
    if (name == n) {
      type = t;
      return true;
    }
  }
  return false;
}

std::size_t byte_size(PlyType t) {
  switch (t) {
    case PlyType::Int8:
    case PlyType::UInt8:
      return 1;
    case PlyType::Int16:
    case PlyType::UInt16:
      return 2;
    case PlyType::Int32:
    case PlyType::UInt32:
    case PlyType::Float32:
      return 4;
    case PlyType::Float64:
      return 8;
  }
  return 8;
}

bool is_integer_type(PlyType t) { return t != PlyType::Float32 && t != PlyType::Float64; }

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::Float32;  // the item type for a list
  bool is_list = false;
  PlyType count_type = PlyType::UInt8;
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

struct PlyHeader {
  PlyFormat format = PlyFormat::Ascii;
  std::vector<PlyElement> elements;
  std::size_t data_begin = 0;  // byte offset of the first byte after "end_header\n"
  int data_line = 1;           // line number of that byte (ascii messages)
};

PlyHeader parse_header(const std::string& bytes, const std::string& source) {
  PlyHeader header;
  std::size_t pos = 0;
  int line = 0;
  bool have_format = false;
  for (;;) {
    std::size_t next = 0;
    const std::size_t end = mesh_reading::line_end(bytes, pos, next);
    if (end == bytes.size())
      fail(ErrorKind::Parse, source, "the PLY header has no end_header line (truncated or not a PLY file)");
    ++line;
    const std::string text = bytes.substr(pos, end - pos);
    pos = next;
    auto error = [&](const std::string& what) { mesh_reading::fail_at_line(ErrorKind::Parse, source, line, what); };
    if (line == 1) {
      if (text != "ply") error("the file does not start with the line 'ply' (not a PLY file?)");
      continue;
    }
    const std::vector<std::string> w = mesh_reading::split_whitespace(text);
    if (w.empty()) continue;
    if (w[0] == "comment" || w[0] == "obj_info") continue;
    if (w[0] == "end_header") {
      if (!have_format) error("end_header before a format line");
      header.data_begin = pos;
      header.data_line = line + 1;
      return header;
    }
    if (w[0] == "format") {
      if (w.size() != 3) error("expected 'format <ascii|binary_little_endian|binary_big_endian> 1.0'");
      if (w[1] == "ascii")
        header.format = PlyFormat::Ascii;
      else if (w[1] == "binary_little_endian")
        header.format = PlyFormat::BinaryLittleEndian;
      else if (w[1] == "binary_big_endian")
        header.format = PlyFormat::BinaryBigEndian;
      else
        error("unknown PLY format '" + mesh_reading::printable(w[1]) + "'");
      if (w[2] != "1.0") error("unsupported PLY version '" + mesh_reading::printable(w[2]) + "' (nearcap reads 1.0)");
      have_format = true;
    } else if (w[0] == "element") {
      if (w.size() != 3) error("expected 'element <name> <count>'");
      char* endp = nullptr;
      errno = 0;
      const unsigned long long count = std::strtoull(w[2].c_str(), &endp, 10);
      if (endp != w[2].c_str() + w[2].size() || w[2][0] == '-' || errno == ERANGE)
        error("element '" + mesh_reading::printable(w[1]) + "' has count '" + mesh_reading::printable(w[2]) +
              "', not a non-negative integer");
      if ((w[1] == "vertex" || w[1] == "face") && std::any_of(header.elements.begin(), header.elements.end(),
                                                              [&](const PlyElement& e) { return e.name == w[1]; }))
        error("a second '" + w[1] + "' element (a mesh has one)");
      header.elements.push_back({w[1], count, {}});
    } else if (w[0] == "property") {
      if (header.elements.empty()) error("a property declared before any element");
      PlyProperty p;
      if (w.size() == 5 && w[1] == "list") {
        p.is_list = true;
        if (!parse_ply_type(w[2], p.count_type) || !is_integer_type(p.count_type))
          error("list count type '" + mesh_reading::printable(w[2]) + "' is not an integer type");
        if (!parse_ply_type(w[3], p.type)) error("unknown property type '" + mesh_reading::printable(w[3]) + "'");
        p.name = w[4];
      } else if (w.size() == 3 && w[1] != "list") {
        if (!parse_ply_type(w[1], p.type)) error("unknown property type '" + mesh_reading::printable(w[1]) + "'");
        p.name = w[2];
      } else {
        error("expected 'property <type> <name>' or 'property list <count type> <item type> <name>'");
      }
      PlyElement& element = header.elements.back();
      if (std::any_of(element.properties.begin(), element.properties.end(),
                      [&](const PlyProperty& q) { return q.name == p.name; }))
        error("element '" + mesh_reading::printable(element.name) + "' declares property '" +
              mesh_reading::printable(p.name) + "' twice");
      element.properties.push_back(p);
    } else {
      error("unknown PLY header line '" + mesh_reading::printable(w[0]) + "'");
    }
  }
}

// Reads the values of the data section one at a time, in the file's encoding.
class PlyValues {
 public:
  PlyValues(const std::string& bytes, const PlyHeader& header, const std::string& source)
      : bytes_(bytes), format_(header.format), source_(source), pos_(header.data_begin), line_(header.data_line) {}

  // The next value as a double (every PLY type converts exactly).  `what`
  // names it in messages.
  double next(PlyType type, const std::string& what) {
    if (format_ == PlyFormat::Ascii) return next_ascii(type, what);
    return next_binary(type, what);
  }

  [[noreturn]] void error(ErrorKind kind, const std::string& what) const {
    if (format_ == PlyFormat::Ascii) mesh_reading::fail_at_line(kind, source_, line_, what);
    fail(kind, source_, "byte " + std::to_string(pos_) + ": " + what);
  }

  // After the last declared element: only whitespace may follow in an ascii
  // file, nothing in a binary one.  `last` names that element in messages.
  void expect_end(const std::string& last) {
    if (format_ == PlyFormat::Ascii) {
      skip_ascii_space();
      if (pos_ >= bytes_.size()) return;
      std::size_t end = pos_;
      while (end < bytes_.size() && !std::isspace(static_cast<unsigned char>(bytes_[end]))) ++end;
      error(ErrorKind::Parse, "found '" + mesh_reading::printable(bytes_.substr(pos_, end - pos_)) + "' after " + last +
                                  " (only whitespace may follow; more entries than declared?)");
    }
    const std::size_t extra = bytes_.size() - pos_;
    if (extra > 0)
      error(ErrorKind::Parse, std::to_string(extra) + (extra == 1 ? " byte" : " bytes") + " after " + last +
                                  " (a binary PLY file ends with its last element)");
  }

 private:
  void skip_ascii_space() {
    while (pos_ < bytes_.size() && std::isspace(static_cast<unsigned char>(bytes_[pos_]))) {
      if (mesh_reading::is_line_end(bytes_, pos_)) ++line_;
      ++pos_;
    }
  }

  double next_ascii(PlyType type, const std::string& what) {
    skip_ascii_space();
    if (pos_ >= bytes_.size())
      error(ErrorKind::Parse, "unexpected end of data, expected " + what + " (truncated file?)");
    const std::size_t start = pos_;
    while (pos_ < bytes_.size() && !std::isspace(static_cast<unsigned char>(bytes_[pos_]))) ++pos_;
    const std::string token = bytes_.substr(start, pos_ - start);
    char* endp = nullptr;
    double value = 0;
    if (is_integer_type(type)) {
      errno = 0;
      const long long v = std::strtoll(token.c_str(), &endp, 10);
      if (endp != token.c_str() + token.size() || errno == ERANGE)
        error(ErrorKind::Parse, "expected " + what + " (an integer), found '" + mesh_reading::printable(token) + "'");
      if (!fits(type, v)) error(ErrorKind::Parse, what + " " + token + " does not fit its declared type");
      value = static_cast<double>(v);
    } else if (type == PlyType::Float32) {
      value = static_cast<double>(std::strtof(token.c_str(), &endp));  // the float32 nearest the decimal
    } else {
      value = std::strtod(token.c_str(), &endp);
    }
    if (endp != token.c_str() + token.size())
      error(ErrorKind::Parse, "expected " + what + ", found '" + mesh_reading::printable(token) + "'");
    return value;
  }

  static bool fits(PlyType type, long long v) {
    switch (type) {
      case PlyType::Int8:
        return v >= INT8_MIN && v <= INT8_MAX;
      case PlyType::UInt8:
        return v >= 0 && v <= UINT8_MAX;
      case PlyType::Int16:
        return v >= INT16_MIN && v <= INT16_MAX;
      case PlyType::UInt16:
        return v >= 0 && v <= UINT16_MAX;
      case PlyType::Int32:
        return v >= INT32_MIN && v <= INT32_MAX;
      case PlyType::UInt32:
        return v >= 0 && v <= static_cast<long long>(UINT32_MAX);
      default:
        return true;
    }
  }

  double next_binary(PlyType type, const std::string& what) {
    const std::size_t n = byte_size(type);
    if (bytes_.size() - pos_ < n)
      error(ErrorKind::Parse, "unexpected end of data, expected " + what + " (truncated file?)");
    std::array<unsigned char, 8> raw{};
    std::memcpy(raw.data(), bytes_.data() + pos_, n);
    pos_ += n;
    const bool little_host = [] {
      const std::uint16_t one = 1;
      unsigned char first = 0;
      std::memcpy(&first, &one, 1);
      return first == 1;
    }();
    if ((format_ == PlyFormat::BinaryLittleEndian) != little_host) std::reverse(raw.begin(), raw.begin() + n);
    auto as = [&](auto zero) {
      decltype(zero) v;
      std::memcpy(&v, raw.data(), sizeof v);
      return static_cast<double>(v);
    };
    switch (type) {
      case PlyType::Int8:
        return as(std::int8_t{});
      case PlyType::UInt8:
        return as(std::uint8_t{});
      case PlyType::Int16:
        return as(std::int16_t{});
      case PlyType::UInt16:
        return as(std::uint16_t{});
      case PlyType::Int32:
        return as(std::int32_t{});
      case PlyType::UInt32:
        return as(std::uint32_t{});
      case PlyType::Float32:
        return as(float{});
      case PlyType::Float64:
        return as(double{});
    }
    return 0;
  }

  const std::string& bytes_;
  PlyFormat format_;
  const std::string& source_;
  std::size_t pos_;
  int line_;
};

}  // namespace

TriangleMesh parse_ply(const std::string& bytes, const std::string& source) {
  const PlyHeader header = parse_header(bytes, source);
  TriangleMesh mesh;
  mesh.source = source;
  PlyValues values(bytes, header, source);
  bool have_vertices = false;
  for (const PlyElement& element : header.elements) {
    if (element.properties.empty()) continue;  // occupies no data
    const bool is_vertex = element.name == "vertex", is_face = element.name == "face";
    std::array<int, 3> xyz{-1, -1, -1};
    int indices = -1;
    for (std::size_t k = 0; k < element.properties.size(); ++k) {
      const PlyProperty& p = element.properties[k];
      if (is_vertex && !p.is_list && p.name.size() == 1 && p.name[0] >= 'x' && p.name[0] <= 'z')
        xyz[static_cast<std::size_t>(p.name[0] - 'x')] = static_cast<int>(k);
      if (is_face && p.is_list && (p.name == "vertex_indices" || p.name == "vertex_index")) {
        if (!is_integer_type(p.type))
          fail(ErrorKind::Parse, source, "the face list '" + p.name + "' has a non-integer item type");
        indices = static_cast<int>(k);
      }
    }
    if (is_vertex) {
      if (xyz[0] < 0 || xyz[1] < 0 || xyz[2] < 0)
        fail(ErrorKind::Parse, source, "the vertex element lacks one of the properties x, y, z");
      have_vertices = true;
      mesh.positions.reserve(static_cast<std::size_t>(std::min<std::uint64_t>(element.count, 1 << 20)));
    }
    if (is_face) {
      if (indices < 0) fail(ErrorKind::Parse, source, "the face element has no vertex_indices list");
      mesh.triangles.reserve(static_cast<std::size_t>(std::min<std::uint64_t>(element.count, 1 << 20)));
    }
    for (std::uint64_t i = 0; i < element.count; ++i) {
      const std::string which = element.name + " " + std::to_string(i);
      Vec3d position{0, 0, 0};
      std::array<VertexIndex, 3> triangle{};
      for (std::size_t k = 0; k < element.properties.size(); ++k) {
        const PlyProperty& p = element.properties[k];
        if (!p.is_list) {
          const double v = values.next(p.type, "property '" + p.name + "' of " + which);
          for (int c = 0; c < 3; ++c)
            if (is_vertex && xyz[static_cast<std::size_t>(c)] == static_cast<int>(k)) position[c] = v;
          continue;
        }
        const double count = values.next(p.count_type, "the list size of '" + p.name + "' of " + which);
        if (count < 0) values.error(ErrorKind::Parse, "negative list size in " + which);
        const bool face_list = is_face && indices == static_cast<int>(k);
        if (face_list && count != 3)
          values.error(ErrorKind::Mesh, "face " + std::to_string(i) + " has " +
                                            std::to_string(static_cast<long long>(count)) +
                                            " vertices; nearcap reads triangle meshes only");
        for (std::uint64_t item = 0; item < static_cast<std::uint64_t>(count); ++item) {
          const double v = values.next(p.type, "item " + std::to_string(item) + " of '" + p.name + "' of " + which);
          if (face_list) {
            if (v < 0)
              values.error(ErrorKind::Mesh, "face " + std::to_string(i) + " refers to vertex " +
                                                std::to_string(static_cast<long long>(v)));
            triangle[static_cast<std::size_t>(item)] = static_cast<VertexIndex>(v);
          }
        }
      }
      if (is_vertex) mesh.positions.push_back(position);
      if (is_face) mesh.triangles.push_back(triangle);
    }
  }
  if (!have_vertices) fail(ErrorKind::Parse, source, "the PLY file declares no vertex element");
  const PlyElement& last = header.elements.back();
  values.expect_end("the last element the header declares ('element " + mesh_reading::printable(last.name) + " " +
                    std::to_string(last.count) + "')");
  mesh_reading::check_read_mesh(mesh);
  return mesh;
}

}  // namespace nearcap
