// Whether a closed mesh's faces meet only where they share edges and
// vertices (see mesh.hpp, mesh_is_embedded): CGAL's self-intersection test,
// whose predicates are exact on the double positions.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include <vector>

#include "nearcap/scene/mesh.hpp"

namespace nearcap {

bool mesh_is_embedded(const TriangleMesh& mesh) {
  using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
  using Surface = CGAL::Surface_mesh<Kernel::Point_3>;
  Surface surface;
  std::vector<Surface::Vertex_index> vertex;
  vertex.reserve(mesh.positions.size());
  for (const Vec3d& p : mesh.positions) vertex.push_back(surface.add_vertex(Kernel::Point_3(p.x, p.y, p.z)));
  for (const auto& t : mesh.triangles)
    if (surface.add_face(vertex[t[0]], vertex[t[1]], vertex[t[2]]) == Surface::null_face()) return false;
  // A degenerate face (zero area) counts as meeting another: not embedded.
  return !CGAL::Polygon_mesh_processing::does_self_intersect<CGAL::Sequential_tag>(surface);
}

}  // namespace nearcap
