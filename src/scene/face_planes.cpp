// Object-space face planes with certified bounds (see FacePlanes in mesh.hpp).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

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
  if (!mesh.triangles.empty()) {
    const double inf = INFINITY;
    fp.box_lo = {inf, inf, inf};
    fp.box_hi = {-inf, -inf, -inf};
    for (const auto& t : mesh.triangles)
      for (VertexIndex v : t)
        for (int a = 0; a < 3; ++a) {
          fp.box_lo[a] = std::fmin(fp.box_lo[a], mesh.positions[v][a]);
          fp.box_hi[a] = std::fmax(fp.box_hi[a], mesh.positions[v][a]);
        }
    // Faces in the Morton order of their centroids (10 bits per axis over the
    // mesh's box), then cut into chunks.
    auto spread = [](std::uint64_t x) {  // 10 bits -> every third of 30
      x &= 0x3ff;
      x = (x | (x << 16)) & 0x30000ff;
      x = (x | (x << 8)) & 0x300f00f;
      x = (x | (x << 4)) & 0x30c30c3;
      x = (x | (x << 2)) & 0x9249249;
      return x;
    };
    std::vector<std::pair<std::uint64_t, FaceIndex>> order(mesh.triangles.size());
    for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
      std::uint64_t code = 0;
      for (int a = 0; a < 3; ++a) {
        const auto& t = mesh.triangles[f];
        const double centroid = (mesh.positions[t[0]][a] + mesh.positions[t[1]][a] + mesh.positions[t[2]][a]) / 3.0;
        const double extent = fp.box_hi[a] - fp.box_lo[a];
        const double u = extent > 0 ? (centroid - fp.box_lo[a]) / extent : 0.0;
        code |= spread(static_cast<std::uint64_t>(std::clamp(u, 0.0, 1.0) * 1023.0)) << a;
      }
      order[f] = {code, static_cast<FaceIndex>(f)};
    }
    std::sort(order.begin(), order.end());
    fp.chunk_faces.reserve(order.size());
    for (std::size_t k = 0; k < order.size(); ++k) {
      const FaceIndex f = order[k].second;
      fp.chunk_faces.push_back(f);
      if (k % FacePlanes::kFacesPerChunk == 0) fp.chunk_box.push_back({Vec3d{inf, inf, inf}, Vec3d{-inf, -inf, -inf}});
      std::array<Vec3d, 2>& chunk = fp.chunk_box.back();
      for (VertexIndex v : mesh.triangles[f])
        for (int a = 0; a < 3; ++a) {
          chunk[0][a] = std::fmin(chunk[0][a], mesh.positions[v][a]);
          chunk[1][a] = std::fmax(chunk[1][a], mesh.positions[v][a]);
        }
    }
  }
  mesh.face_planes = std::move(fp);
}

}  // namespace nearcap
