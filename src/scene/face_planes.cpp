// Object-space face planes with certified bounds (see FacePlanes in mesh.hpp).
#include <cmath>

#include "nearcap/numeric/bounded_double.hpp"
#include "nearcap/scene/mesh.hpp"

namespace nearcap {

void compute_face_planes(TriangleMesh& mesh) {
  FacePlanes fp;
  fp.plane.resize(mesh.triangles.size());
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    const auto& t = mesh.triangles[f];
    // Mesh coordinates are exact doubles: BoundedDouble bounds the rounding.
    const Vec3<BoundedDouble> a(mesh.positions[t[0]]), b(mesh.positions[t[1]]), c(mesh.positions[t[2]]);
    const Vec3<BoundedDouble> n = cross(b - a, c - a);
    const BoundedDouble d = dot(n, a);
    fp.plane[f] = {n.x.v, n.y.v, n.z.v, d.v};
    for (int i = 0; i < 3; ++i) {
      fp.n_error = std::fmax(fp.n_error, n[i].e);
      fp.n_max = std::fmax(fp.n_max, std::fabs(n[i].v) + n[i].e);
    }
    fp.d_error = std::fmax(fp.d_error, d.e);
    fp.d_max = std::fmax(fp.d_max, std::fabs(d.v) + d.e);
  }
  mesh.face_planes = std::move(fp);
}

}  // namespace nearcap
