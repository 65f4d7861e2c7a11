// nearcap/io/cgal_adapter.hpp — a CGAL Surface_mesh as a TriangleMesh.
//
// Header-only, for a program that uses CGAL: the one nearcap header that
// includes a CGAL header (its number utilities, for CGAL::to_double); the
// program's translation unit carries CGAL's compile flags.  Vertices in the
// mesh's iteration order (removed elements skipped), faces in theirs, each
// face's vertices as vertices_around_face gives them.  Coordinates go through CGAL::to_double:
// exact for kernels with double coordinates (Epick, Simple_cartesian<double>),
// rounded to nearest for exact kernels (then the rounded doubles are the
// scene, as for any number read from a file).  A face that is not a triangle
// is an Error(Mesh) naming it; everything else is checked by
// SceneBuilder::build(), exactly as for a file.
#pragma once

#include <CGAL/number_utils.h>

#include <array>
#include <string>
#include <unordered_map>

#include "nearcap/error.hpp"
#include "nearcap/scene/mesh.hpp"

namespace nearcap {

template <class SurfaceMesh>
TriangleMesh mesh_from_cgal(const SurfaceMesh& mesh, const std::string& source) {
  TriangleMesh out;
  out.source = source;
  std::unordered_map<std::size_t, VertexIndex> index;  // CGAL vertex index -> position in out
  for (auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    index.emplace(static_cast<std::size_t>(v), static_cast<VertexIndex>(out.positions.size()));
    out.positions.push_back({CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())});
  }
  std::size_t f_number = 0;
  for (auto f : mesh.faces()) {
    std::array<VertexIndex, 3> t{};
    std::size_t n = 0;
    for (auto v : mesh.vertices_around_face(mesh.halfedge(f))) {
      if (n < 3) t[n] = index.at(static_cast<std::size_t>(v));
      ++n;
    }
    if (n != 3)
      throw Error(ErrorKind::Mesh, source + ": face " + std::to_string(f_number) + " has " + std::to_string(n) +
                                       " vertices; nearcap needs triangles (CGAL::Polygon_mesh_processing::"
                                       "triangulate_faces first)");
    out.triangles.push_back(t);
    ++f_number;
  }
  return out;
}

}  // namespace nearcap
