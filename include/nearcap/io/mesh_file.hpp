// nearcap/io/mesh_file.hpp — mesh files into TriangleMesh.
//
// Every format is parsed by nearcap itself (src/io/mesh_file.cpp says why not
// OpenMesh's readers); faces are kept exactly as written, so the validation
// (scene/mesh.hpp) reports the faults a topology-building reader would hide.
// Files are read as io/input_files.hpp says: regular files only, bounded.
#pragma once

#include <string>

#include "nearcap/scene/mesh.hpp"

namespace nearcap {

// Reads OFF, OBJ, PLY or STL (chosen by extension, case-insensitive).  Checks
// syntax, finiteness of every coordinate, index ranges, and that every face is
// a triangle with three distinct vertices.  Throws nearcap::Error (Io, Parse,
// NonFinite or Mesh) naming the file and the element.
TriangleMesh read_mesh(const std::string& path);

// Same, from bytes in memory; `format` is "off", "obj", "ply" or "stl" and
// `source` names the data in messages.  (Used by the fuzzers.)
TriangleMesh parse_mesh(const std::string& bytes, const std::string& format, const std::string& source);

// Parses OFF text ("OFF" header, optional '#' comments anywhere, optional
// per-face colour values after the indices).  `source` names it in messages.
TriangleMesh parse_off(const std::string& text, const std::string& source);

// Parses Wavefront OBJ text: "v x y z" vertices (a fourth value must be 1;
// six or seven values carry colours, ignored), "f" triangles whose entries are
// "i", "i/t", "i//n" or "i/t/n" with 1-based or negative (relative) position
// indices referring to vertices defined before the face; '#' comments and '\'
// line continuations.  Texture, normal, group and material statements are
// skipped; free-form geometry and unknown statements are errors.
TriangleMesh parse_obj(const std::string& text, const std::string& source);

// Parses PLY 1.0 (ascii, binary little- or big-endian): the "vertex"
// element's x, y, z (any numeric type, kept at its declared precision) and the
// "face" element's "vertex_indices" (or "vertex_index") list; other elements
// and properties are skipped by their declared types.
TriangleMesh parse_ply(const std::string& bytes, const std::string& source);

// Parses STL, binary (exactly 84 + 50 n bytes) or ascii ("solid" ...): one
// triangle per facet, equal positions shared as one vertex, float32
// coordinates, stored normals ignored.
TriangleMesh parse_stl(const std::string& bytes, const std::string& source);

}  // namespace nearcap
