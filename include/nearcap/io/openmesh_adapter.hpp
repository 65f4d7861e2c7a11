// nearcap/io/openmesh_adapter.hpp — an OpenMesh triangle mesh as a TriangleMesh.
//
// Header-only: include it where OpenMesh is already included (nearcap itself
// does not link OpenMesh).  Works with any OpenMesh mesh type whose points
// have three coordinates (TriMesh_ArrayKernelT<>, PolyMesh_ArrayKernelT<> with
// triangle faces): vertices in OpenMesh's index order, faces in its order with
// their vertices as the face circulates them.  Coordinates are converted to
// double exactly (OpenMesh's default point type is float).  A face that is not
// a triangle is an Error(Mesh) naming it; everything else is checked by
// SceneBuilder::build(), exactly as for a file.
#pragma once

#include <array>
#include <string>

#include "nearcap/error.hpp"
#include "nearcap/scene/mesh.hpp"

namespace nearcap {

template <class OpenMeshMesh>
TriangleMesh mesh_from_openmesh(const OpenMeshMesh& mesh, const std::string& source) {
  TriangleMesh out;
  out.source = source;
  out.positions.reserve(mesh.n_vertices());
  for (std::size_t v = 0; v < mesh.n_vertices(); ++v) {
    const auto& p = mesh.point(mesh.vertex_handle(static_cast<unsigned>(v)));
    out.positions.push_back({static_cast<double>(p[0]), static_cast<double>(p[1]), static_cast<double>(p[2])});
  }
  out.triangles.reserve(mesh.n_faces());
  for (std::size_t f = 0; f < mesh.n_faces(); ++f) {
    std::array<VertexIndex, 3> t{};
    std::size_t n = 0;
    for (auto v : mesh.fv_range(mesh.face_handle(static_cast<unsigned>(f)))) {
      if (n < 3) t[n] = static_cast<VertexIndex>(v.idx());
      ++n;
    }
    if (n != 3)
      throw Error(ErrorKind::Mesh, source + ": face " + std::to_string(f) + " has " + std::to_string(n) +
                                       " vertices; nearcap needs triangles (triangulate first)");
    out.triangles.push_back(t);
  }
  return out;
}

}  // namespace nearcap
