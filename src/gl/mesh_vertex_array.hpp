// gl/mesh_vertex_array.hpp — an object's mesh as the depth pre-pass and the
// near-cap pass draw it (private to gl/; not installed).
//
// The draw is a triangle list, three corners per triangle in the mesh's
// order (what glDrawArrays submits), each corner the float32 point (x, y, z,
// 1) of its mesh vertex.  A vertex program's output depends on its input
// alone, so the program is run once per mesh vertex and its outputs are
// gathered per corner (as a GL's post-transform cache reuses them in an
// indexed draw): the same bits as running it per corner, with a sixth of the
// runs on a closed mesh.
#pragma once

#include <vector>

#include "nearcap/gl/shadow_vertex_programs.hpp"
#include "nearcap/scene/mesh.hpp"

namespace nearcap::gl {

struct MeshVertexArray {
  const TriangleMesh* mesh = nullptr;  // outlives the array
  std::vector<ShadowVertex> vertices;  // one per mesh vertex
};

MeshVertexArray mesh_vertex_array(const TriangleMesh& mesh);

// The draw's inputs, one per corner (a recorded draw call's, which a real GL
// runs its own program on).
std::vector<ShadowVertex> corners(const MeshVertexArray& a);

// The clip-space vertex of each corner: run_vertex_program(p, u, corners(a))
// bit for bit.
std::vector<Vec4f> run_vertex_program(VertexProgram p, const ShadowUniforms& u, const MeshVertexArray& a);

}  // namespace nearcap::gl
