// gl/mesh_vertex_array.hpp — an object's mesh as indexed draws read it:
// the depth pre-pass and the near-cap pass draw the mesh, Z-fail's light and
// dark caps its light-facing and other triangles (private to gl/; not
// installed).
//
// A draw is a triangle list, three corners per triangle (what glDrawArrays
// submits), each corner the float32 point (x, y, z, 1) of its mesh vertex,
// or for the dark cap the direction (x, y, z, 0).  A vertex program's output
// depends on its input alone, so the program is run once per mesh vertex and
// its outputs are gathered per corner (as a GL's post-transform cache reuses
// them in an indexed draw): the same bits as running it per corner, with a
// sixth of the runs on a closed mesh; and the setup codes, divides and snaps
// each vertex once (Framebuffer::set_up of an indexed draw).
#pragma once

#include <cstdint>
#include <vector>

#include "nearcap/gl/shadow_vertex_programs.hpp"
#include "nearcap/scene/mesh.hpp"

namespace nearcap::gl {

// An indexed draw's inputs: corner k of its triangle list is inputs[corners[k]].
struct IndexedInputs {
  const std::vector<ShadowVertex>& inputs;
  const std::vector<std::uint32_t>& corners;
};

struct MeshVertexArray {
  std::vector<ShadowVertex> vertices;        // (x, y, z, 1) per mesh vertex
  std::vector<ShadowVertex> directions;      // (x, y, z, 0) per mesh vertex
  std::vector<std::uint32_t> corner_vertex;  // the mesh's triangles' vertices, 3 per triangle, in order
  IndexedInputs draw() const { return {vertices, corner_vertex}; }
};

MeshVertexArray mesh_vertex_array(const TriangleMesh& mesh);

// One value per corner, in order, from one per input.
template <class T>
std::vector<T> per_corner(const std::vector<T>& per_input, const std::vector<std::uint32_t>& corners) {
  std::vector<T> out;
  out.reserve(corners.size());
  for (std::uint32_t k : corners) out.push_back(per_input[k]);
  return out;
}

// The draw's inputs, one per corner (a recorded draw call's, which a real GL
// runs its own program on).
std::vector<ShadowVertex> corners(const MeshVertexArray& a);

}  // namespace nearcap::gl
