// Occluder validation: closed, consistently oriented, vertex-manifold, outward.
//
// Works on directed half-edges (a -> b, one per face corner).  A closed,
// consistently oriented 2-manifold has every directed half-edge exactly once and
// its twin (b -> a) exactly once; the faces around every vertex form one cycle;
// and its signed volume is positive when the orientation is outward.  Faults
// are reported in face order, so the "first offending edge" is reproducible.
#include <algorithm>
#include <cstdint>
#include <limits>
#include <memory>
#include <mutex>
#include <sstream>
#include <vector>

#include "nearcap/error.hpp"
#include "nearcap/numeric/bounded_double.hpp"
#include "nearcap/numeric/rational.hpp"
#include "nearcap/scene/mesh.hpp"

namespace nearcap {
namespace {

std::string edge_name(VertexIndex a, VertexIndex b) {
  std::ostringstream s;
  s << "edge (" << std::min(a, b) << ", " << std::max(a, b) << ")";
  return s.str();
}

[[noreturn]] void mesh_fault(const TriangleMesh& mesh, const std::string& what) {
  throw Error(ErrorKind::Mesh, mesh.source + ": " + what);
}

constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();

// A half-edge a -> b of face f, corner k (a = triangles[f][k], b the next
// corner), as a sort key: its edge {min, max}, then its direction (0 from
// the smaller vertex, 1 from the larger; 0 for a loop a -> a), then its index
// 3f + k.
struct HalfEdge {
  std::uint64_t edge;
  std::uint64_t direction_index;
  std::uint32_t direction() const { return static_cast<std::uint32_t>(direction_index >> 63); }
  std::size_t index() const { return static_cast<std::size_t>(direction_index & ~(std::uint64_t{1} << 63)); }
  FaceIndex face() const { return static_cast<FaceIndex>(index() / 3); }
  int corner() const { return static_cast<int>(index() % 3); }
  bool loop() const { return (edge >> 32) == (edge & 0xFFFFFFFFu); }
  bool operator<(const HalfEdge& o) const {
    return edge != o.edge ? edge < o.edge : direction_index < o.direction_index;
  }
};

// Every half-edge of the mesh sorted by HalfEdge's key: the half-edges of one
// edge form a run, each direction's in face order.  Sorting, not a hash map:
// a mesh of 75,000 faces has 226,000 half-edges.
class EdgeRuns {
 public:
  explicit EdgeRuns(const TriangleMesh& mesh) {
    sorted_.reserve(mesh.triangles.size() * 3);
    for (std::size_t f = 0; f < mesh.triangles.size(); ++f)
      for (int k = 0; k < 3; ++k) {
        const VertexIndex a = mesh.triangles[f][k], b = mesh.triangles[f][(k + 1) % 3];
        const std::uint64_t direction = a > b ? 1 : 0;
        sorted_.push_back({(std::uint64_t(std::min(a, b)) << 32) | std::max(a, b), (direction << 63) | (3 * f + k)});
      }
    std::sort(sorted_.begin(), sorted_.end());
  }
  // visit(first half-edge of the run, its length), for every run.
  template <class Visit>
  void each_run(Visit&& visit) const {
    for (std::size_t i = 0; i < sorted_.size();) {
      std::size_t j = i + 1;
      while (j < sorted_.size() && sorted_[j].edge == sorted_[i].edge) ++j;
      visit(&sorted_[i], j - i);
      i = j;
    }
  }

 private:
  std::vector<HalfEdge> sorted_;
};

// The twin of half-edge h a -> b in its run: the first half-edge b -> a in
// face order (for a loop a -> a, the first a -> a: h or one before it);
// nullptr where there is none.
const HalfEdge* twin_in_run(const HalfEdge* run, std::size_t n, const HalfEdge& h) {
  const std::uint32_t wanted = h.loop() ? h.direction() : 1 - h.direction();
  for (std::size_t i = 0; i < n; ++i)
    if (run[i].direction() == wanted) return &run[i];
  return nullptr;
}

// neighbours[f][k]: the face of half-edge (f, k)'s twin, kNoFace without one.
void fill_neighbours(TriangleMesh& mesh, const EdgeRuns& runs) {
  mesh.neighbours.assign(mesh.triangles.size(), {kNoFace, kNoFace, kNoFace});
  runs.each_run([&](const HalfEdge* run, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i)
      if (const HalfEdge* twin = twin_in_run(run, n, run[i]))
        mesh.neighbours[run[i].face()][run[i].corner()] = twin->face();
  });
}

// Sign of the signed volume (times 6) of `triangles` (of the mesh's
// positions), exactly: filter first, rationals if needed.
Sign signed_volume_sign(const TriangleMesh& mesh, const std::vector<std::array<VertexIndex, 3>>& triangles) {
  const Vec3d r = mesh.positions[triangles.front()[0]];
  BoundedDouble sum(0.0);
  for (const auto& t : triangles) {
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
  for (const auto& t : triangles) {
    const Vec3<Rational> a = to_rational(mesh.positions[t[0]]) - rr;
    const Vec3<Rational> b = to_rational(mesh.positions[t[1]]) - rr;
    const Vec3<Rational> c = to_rational(mesh.positions[t[2]]) - rr;
    exact += dot(a, cross(b, c));
  }
  return sign_of(exact);
}

// Whether every connected component (across shared edges) of a closed mesh
// of positive signed volume has a positive signed volume of its own.
bool components_outward(const TriangleMesh& mesh) {
  const std::size_t nf = mesh.triangles.size();
  std::vector<bool> reached(nf, false);
  std::vector<std::array<VertexIndex, 3>> component;
  std::vector<FaceIndex> stack;
  for (FaceIndex seed = 0; seed < nf; ++seed) {
    if (reached[seed]) continue;
    component.clear();
    stack.assign(1, seed);
    reached[seed] = true;
    while (!stack.empty()) {
      const FaceIndex f = stack.back();
      stack.pop_back();
      component.push_back(mesh.triangles[f]);
      for (FaceIndex g : mesh.neighbours[f])
        if (!reached[g]) {
          reached[g] = true;
          stack.push_back(g);
        }
    }
    if (component.size() == nf) return true;  // one component: the whole mesh's volume
    if (signed_volume_sign(mesh, component) != Sign::Positive) return false;
  }
  return true;
}

}  // namespace

// bounds_outward_solids()'s answer, decided once for a validated mesh and
// the copies that share it.
struct OutwardSolidsAnswer {
  std::once_flag decided;
  bool value = false;
};

bool TriangleMesh::bounds_outward_solids() const {
  if (!outward_solids) return false;
  std::call_once(outward_solids->decided,
                 [&] { outward_solids->value = components_outward(*this) && mesh_is_embedded(*this); });
  return outward_solids->value;
}

void build_adjacency(TriangleMesh& mesh) { fill_neighbours(mesh, EdgeRuns(mesh)); }

void validate_occluder(TriangleMesh& mesh) {
  mesh.outward_solids.reset();  // a mesh that fails validation answers false
  if (mesh.triangles.empty()) mesh_fault(mesh, "the mesh has no faces (empty mesh)");
  const std::size_t nf = mesh.triangles.size();
  const EdgeRuns runs(mesh);
  // Each check reports its first fault in face order (then corner order):
  // the half-edge of smallest index among the offending ones.
  std::size_t first = kNone;
  std::uint32_t shared = 0;
  // Non-manifold edges first: they also produce duplicate directed half-edges.
  runs.each_run([&](const HalfEdge* run, std::size_t n) {
    if (n <= 2) return;
    for (std::size_t i = 0; i < n; ++i)
      if (run[i].index() < first) {
        first = run[i].index();
        shared = static_cast<std::uint32_t>(n);
      }
  });
  auto corner_edge = [&mesh](std::size_t index) {
    const auto& t = mesh.triangles[index / 3];
    return std::pair<VertexIndex, VertexIndex>{t[index % 3], t[(index % 3 + 1) % 3]};
  };
  if (first != kNone) {
    const auto [a, b] = corner_edge(first);
    mesh_fault(mesh, edge_name(a, b) + " is shared by " + std::to_string(shared) +
                         " faces (non-manifold edge; first at face " + std::to_string(first / 3) + ")");
  }
  // Every run now holds one or two half-edges.  Two in the same direction:
  // the second (in face order) repeats the first.
  std::size_t earlier = kNone;
  runs.each_run([&](const HalfEdge* run, std::size_t n) {
    if (n == 2 && run[0].direction() == run[1].direction() && run[1].index() < first) {
      first = run[1].index();
      earlier = run[0].index();
    }
  });
  if (first != kNone) {
    const auto [a, b] = corner_edge(first);
    mesh_fault(mesh, edge_name(a, b) + " is traversed in the same direction by faces " + std::to_string(earlier / 3) +
                         " and " + std::to_string(first / 3) + " (inconsistent orientation)");
  }
  // A half-edge without its twin (b -> a): alone in its run.
  runs.each_run([&](const HalfEdge* run, std::size_t n) {
    if (n == 1 && !twin_in_run(run, n, run[0]) && run[0].index() < first) first = run[0].index();
  });
  if (first != kNone) {
    const auto [a, b] = corner_edge(first);
    mesh_fault(mesh, edge_name(a, b) + " of face " + std::to_string(first / 3) +
                         " has no neighbouring face (open mesh: boundary edge)");
  }
  fill_neighbours(mesh, runs);

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

  const Sign volume = signed_volume_sign(mesh, mesh.triangles);
  if (volume == Sign::Negative)
    mesh_fault(
        mesh,
        "the signed volume is negative: faces are oriented inward (expected counter-clockwise seen from outside)");
  if (volume == Sign::Zero) mesh_fault(mesh, "the signed volume is zero (a flat or self-cancelling closed mesh)");
  mesh.outward_solids = std::make_shared<OutwardSolidsAnswer>();
}

}  // namespace nearcap
