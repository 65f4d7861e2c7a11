// nearcap/scene/mesh.hpp — triangle meshes: positions and topology, nothing else.
//
// A TriangleMesh is what a scene object needs: vertex positions in object space
// (doubles, exactly as read) and triangles as vertex-index triples, in the
// file's order.  Occluders must be closed, consistently outward-oriented
// 2-manifolds; validate_occluder() proves it and fills the face adjacency the
// silhouette extraction walks.
//
// Reading is io/mesh_file.hpp's; adapters from OpenMesh and CGAL meshes are
// io/openmesh_adapter.hpp and io/cgal_adapter.hpp.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "nearcap/numeric/vec3.hpp"

namespace nearcap {

using VertexIndex = std::uint32_t;
using FaceIndex = std::uint32_t;
inline constexpr FaceIndex kNoFace = 0xffffffffu;

// Object-space plane of every face, n = (b - a) x (c - a) and d = n . a, as
// doubles, with bounds over the mesh: |exact - stored| <= n_error (each
// component of n) and d_error; |n_i| <= n_max, |d| <= d_max.  Orientation
// tests against a point in object space are then n . p - d: no vertex gathers.
// Also object-space boxes of the triangles' vertices (exact: min and max of
// the stored doubles), for culls that must not visit every face per frame:
// the whole mesh's, and one per chunk of kFacesPerChunk faces that lie near
// each other (the faces in the Morton order of their centroids, cut into
// runs).
struct FacePlanes {
  static constexpr std::size_t kFacesPerChunk = 256;
  std::vector<std::array<double, 4>> plane;  // n.x, n.y, n.z, d
  double n_error = 0, d_error = 0, n_max = 0, d_max = 0;
  Vec3d box_lo{0, 0, 0}, box_hi{0, 0, 0};       // empty mesh: both 0
  std::vector<FaceIndex> chunk_faces;           // every face once, chunk by chunk
  std::vector<std::array<Vec3d, 2>> chunk_box;  // chunk k: chunk_faces[k * kFacesPerChunk, ...)
};

struct OutwardSolidsAnswer;  // mesh_validation.cpp

struct TriangleMesh {
  std::string source;                                 // file it was read from (for messages)
  std::vector<Vec3d> positions;                       // object space
  std::vector<std::array<VertexIndex, 3>> triangles;  // counter-clockwise seen from outside
  // neighbours[f][k]: the face across edge (triangles[f][k], triangles[f][(k+1)%3]);
  // filled by validate_occluder(), empty before.
  std::vector<std::array<FaceIndex, 3>> neighbours;
  // Filled by compute_face_planes(); empty before.
  FacePlanes face_planes;
  // Whether the mesh is the outward surface of the solids it bounds: its
  // faces meet only where they share edges and vertices (mesh_is_embedded),
  // and every connected component (across shared edges) has a positive
  // signed volume of its own (none turned inside out, no cavity).  So a ray
  // from outside meets a face turned toward it first.  False before
  // validate_occluder(); after it, decided at the first call and remembered
  // for the mesh and its copies (its self-intersection test is dear on a
  // large mesh, and most commands never ask).  Safe to call from several
  // threads.
  bool bounds_outward_solids() const;
  // Set by validate_occluder(): what bounds_outward_solids() remembers.
  std::shared_ptr<OutwardSolidsAnswer> outward_solids;

  std::size_t triangle_count() const { return triangles.size(); }
  bool has_adjacency() const { return neighbours.size() == triangles.size(); }
};

// Proves the mesh is a closed, consistently oriented 2-manifold with positive
// signed volume (outward orientation), and fills `neighbours`.  Zero-area
// triangles, duplicate positions and unreferenced vertices are legal.  Throws
// nearcap::Error(Mesh) naming the first offending edge or vertex, in face order.
void validate_occluder(TriangleMesh& mesh);

// Whether the faces meet only where they share edges and vertices (exact
// predicates; a zero-area face meets its neighbours: false).  What
// bounds_outward_solids() costs at its first call on a large mesh
// (docs/findings/sweep-speed.md).
bool mesh_is_embedded(const TriangleMesh& mesh);

// Fills `face_planes` (certified, from the exact double vertices).
void compute_face_planes(TriangleMesh& mesh);

// Fills `neighbours` for a mesh that may be open (receivers): kNoFace marks a
// boundary edge.  Never throws.
void build_adjacency(TriangleMesh& mesh);

}  // namespace nearcap
