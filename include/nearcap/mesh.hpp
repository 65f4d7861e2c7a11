// nearcap/mesh.hpp — triangle meshes: positions and topology, nothing else.
//
// A TriangleMesh is what a scene object needs: vertex positions in object space
// (doubles, exactly as read) and triangles as vertex-index triples, in the
// file's order.  Occluders must be closed, consistently outward-oriented
// 2-manifolds; validate_occluder() proves it and fills the face adjacency the
// silhouette extraction walks.
//
// Reading: every format is parsed by nearcap itself (mesh_io.cpp says why
// not OpenMesh's readers); faces are kept exactly as written, so the
// validation reports the faults a topology-building reader would hide.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "nearcap/vec3.hpp"

namespace nearcap {

using VertexIndex = std::uint32_t;
using FaceIndex = std::uint32_t;
inline constexpr FaceIndex kNoFace = 0xffffffffu;

// Object-space plane of every face, n = (b - a) x (c - a) and d = n . a, as
// doubles, with bounds over the mesh: |exact - stored| <= n_error (each
// component of n) and d_error; |n_i| <= n_max, |d| <= d_max.  Orientation
// tests against a point in object space are then n . p - d: no vertex gathers.
struct FacePlanes {
  std::vector<std::array<double, 4>> plane;  // n.x, n.y, n.z, d
  double n_error = 0, d_error = 0, n_max = 0, d_max = 0;
};

struct TriangleMesh {
  std::string source;                                 // file it was read from (for messages)
  std::vector<Vec3d> positions;                       // object space
  std::vector<std::array<VertexIndex, 3>> triangles;  // counter-clockwise seen from outside
  // neighbours[f][k]: the face across edge (triangles[f][k], triangles[f][(k+1)%3]);
  // filled by validate_occluder(), empty before.
  std::vector<std::array<FaceIndex, 3>> neighbours;
  // Filled by compute_face_planes(); empty before.
  FacePlanes face_planes;

  std::size_t triangle_count() const { return triangles.size(); }
  bool has_adjacency() const { return neighbours.size() == triangles.size(); }
};

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

// Proves the mesh is a closed, consistently oriented 2-manifold with positive
// signed volume (outward orientation), and fills `neighbours`.  Zero-area
// triangles, duplicate positions and unreferenced vertices are legal.  Throws
// nearcap::Error(Mesh) naming the first offending edge or vertex, in face order.
void validate_occluder(TriangleMesh& mesh);

// Fills `face_planes` (certified, from the exact double vertices).
void compute_face_planes(TriangleMesh& mesh);

// Fills `neighbours` for a mesh that may be open (receivers): kNoFace marks a
// boundary edge.  Never throws.
void build_adjacency(TriangleMesh& mesh);

}  // namespace nearcap
