// Occluder validation: closed, consistently oriented, vertex-manifold, outward.
//
// Works on directed half-edges (a -> b, one per face corner).  A closed,
// consistently oriented 2-manifold has every directed half-edge exactly once and
// its twin (b -> a) exactly once; the faces around every vertex form one cycle;
// and its signed volume is positive when the orientation is outward.  Faults
// are reported in face order, so the "first offending edge" is reproducible.
#include <algorithm>
#include <cstdint>
#include <sstream>
#include <unordered_map>

#include "nearcap/error.hpp"
#include "nearcap/numeric/bounded_double.hpp"
#include "nearcap/numeric/rational.hpp"
#include "nearcap/scene/mesh.hpp"

namespace nearcap {
namespace {

std::uint64_t key(VertexIndex a, VertexIndex b) { return (std::uint64_t(a) << 32) | b; }

std::string edge_name(VertexIndex a, VertexIndex b) {
  std::ostringstream s;
  s << "edge (" << std::min(a, b) << ", " << std::max(a, b) << ")";
  return s.str();
}

[[noreturn]] void mesh_fault(const TriangleMesh& mesh, const std::string& what) {
  throw Error(ErrorKind::Mesh, mesh.source + ": " + what);
}

// Directed half-edge -> (face, corner).  Returns the first duplicate, if any.
struct HalfedgeTable {
  std::unordered_map<std::uint64_t, std::uint64_t> owner;  // key(a,b) -> face*3+corner
};

// Sign of the signed volume (times 6), exactly: filter first, rationals if needed.
Sign signed_volume_sign(const TriangleMesh& mesh) {
  const Vec3d r = mesh.positions[mesh.triangles.front()[0]];
  BoundedDouble sum(0.0);
  for (const auto& t : mesh.triangles) {
    Vec3<BoundedDouble> p[3];
    for (int k = 0; k < 3; ++k) {
      const Vec3d& q = mesh.positions[t[k]];
      p[k] = {BoundedDouble(q.x) - BoundedDouble(r.x), BoundedDouble(q.y) - BoundedDouble(r.y),
              BoundedDouble(q.z) - BoundedDouble(r.z)};
    }
    sum += dot(p[0], cross(p[1], p[2]));
  }
  if (auto s = sum.sign()) return *s;
  const Vec3<Rational> rr = to_rational(r);
  Rational exact(0);
  for (const auto& t : mesh.triangles) {
    const Vec3<Rational> a = to_rational(mesh.positions[t[0]]) - rr;
    const Vec3<Rational> b = to_rational(mesh.positions[t[1]]) - rr;
    const Vec3<Rational> c = to_rational(mesh.positions[t[2]]) - rr;
    exact += dot(a, cross(b, c));
  }
  return sign_of(exact);
}

}  // namespace

void build_adjacency(TriangleMesh& mesh) {
  std::unordered_map<std::uint64_t, FaceIndex> face_of;
  face_of.reserve(mesh.triangles.size() * 3);
  for (FaceIndex f = 0; f < mesh.triangles.size(); ++f) {
    const auto& t = mesh.triangles[f];
    for (int k = 0; k < 3; ++k) face_of.emplace(key(t[k], t[(k + 1) % 3]), f);
  }
  mesh.neighbours.assign(mesh.triangles.size(), {kNoFace, kNoFace, kNoFace});
  for (FaceIndex f = 0; f < mesh.triangles.size(); ++f) {
    const auto& t = mesh.triangles[f];
    for (int k = 0; k < 3; ++k) {
      const auto it = face_of.find(key(t[(k + 1) % 3], t[k]));
      if (it != face_of.end()) mesh.neighbours[f][k] = it->second;
    }
  }
}

void validate_occluder(TriangleMesh& mesh) {
  if (mesh.triangles.empty()) mesh_fault(mesh, "the mesh has no faces (empty mesh)");
  const std::size_t nf = mesh.triangles.size();
  std::unordered_map<std::uint64_t, std::uint32_t> directed;  // key(a,b) -> face
  directed.reserve(nf * 3);
  std::unordered_map<std::uint64_t, std::uint32_t> undirected_count;
  undirected_count.reserve(nf * 3);
  for (FaceIndex f = 0; f < nf; ++f) {
    const auto& t = mesh.triangles[f];
    for (int k = 0; k < 3; ++k) {
      const VertexIndex a = t[k], b = t[(k + 1) % 3];
      ++undirected_count[key(std::min(a, b), std::max(a, b))];
    }
  }
  // Non-manifold edges first: they also produce duplicate directed half-edges.
  for (FaceIndex f = 0; f < nf; ++f) {
    const auto& t = mesh.triangles[f];
    for (int k = 0; k < 3; ++k) {
      const VertexIndex a = t[k], b = t[(k + 1) % 3];
      const std::uint32_t n = undirected_count[key(std::min(a, b), std::max(a, b))];
      if (n > 2)
        mesh_fault(mesh, edge_name(a, b) + " is shared by " + std::to_string(n) +
                             " faces (non-manifold edge; first at face " + std::to_string(f) + ")");
    }
  }
  for (FaceIndex f = 0; f < nf; ++f) {
    const auto& t = mesh.triangles[f];
    for (int k = 0; k < 3; ++k) {
      const VertexIndex a = t[k], b = t[(k + 1) % 3];
      const auto [it, inserted] = directed.emplace(key(a, b), f);
      if (!inserted)
        mesh_fault(mesh, edge_name(a, b) + " is traversed in the same direction by faces " +
                             std::to_string(it->second) + " and " + std::to_string(f) + " (inconsistent orientation)");
    }
  }
  for (FaceIndex f = 0; f < nf; ++f) {
    const auto& t = mesh.triangles[f];
    for (int k = 0; k < 3; ++k) {
      const VertexIndex a = t[k], b = t[(k + 1) % 3];
      if (directed.find(key(b, a)) == directed.end())
        mesh_fault(mesh, edge_name(a, b) + " of face " + std::to_string(f) +
                             " has no neighbouring face (open mesh: boundary edge)");
    }
  }
  build_adjacency(mesh);

  // Vertex manifoldness: walking around v through twins must visit every face at v.
  std::vector<std::uint32_t> faces_at(mesh.positions.size(), 0);
  std::vector<std::pair<FaceIndex, int>> some_corner(mesh.positions.size(), {kNoFace, 0});
  for (FaceIndex f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const VertexIndex v = mesh.triangles[f][k];
      ++faces_at[v];
      if (some_corner[v].first == kNoFace) some_corner[v] = {f, k};
    }
  for (VertexIndex v = 0; v < mesh.positions.size(); ++v) {
    if (faces_at[v] == 0) continue;  // unreferenced vertex: legal, ignored
    auto [f, k] = some_corner[v];
    std::uint32_t visited = 0;
    const FaceIndex start = f;
    do {
      // Corner k of face f is v; the edge entering v is (k+2 -> k); cross it.
      const FaceIndex g = mesh.neighbours[f][(k + 2) % 3];
      const auto& tg = mesh.triangles[g];
      int kg = 0;
      while (tg[kg] != v) ++kg;
      f = g;
      k = kg;
      ++visited;
    } while (f != start && visited <= faces_at[v]);
    if (visited != faces_at[v])
      mesh_fault(mesh, "vertex " + std::to_string(v) + " has " + std::to_string(faces_at[v]) +
                           " incident faces in more than one fan (non-manifold vertex)");
  }

  const Sign volume = signed_volume_sign(mesh);
  if (volume == Sign::Negative)
    mesh_fault(
        mesh,
        "the signed volume is negative: faces are oriented inward (expected counter-clockwise seen from outside)");
  if (volume == Sign::Zero) mesh_fault(mesh, "the signed volume is zero (a flat or self-cancelling closed mesh)");
}

}  // namespace nearcap
