// Shadow-volume vertex arrays (see shadow_volume_geometry.hpp).
#include "nearcap/gl/shadow_volume_geometry.hpp"

#include <array>
#include <cstring>
#include <map>

namespace nearcap::gl {
namespace {

ShadowVertex at(const Vec3d& p, float w) {
  return {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z), w};
}

void add_quad(std::vector<ShadowVertex>& out, const ShadowVertex& v0, const ShadowVertex& v1, const ShadowVertex& v2,
              const ShadowVertex& v3) {
  out.insert(out.end(), {v0, v1, v2, v0, v2, v3});
}

// A position's bits: the key by which quads chain.
std::array<std::uint32_t, 3> bits(const ShadowVertex& v) {
  std::array<std::uint32_t, 3> out{};
  std::memcpy(&out[0], &v.x, 4);
  std::memcpy(&out[1], &v.y, 4);
  std::memcpy(&out[2], &v.z, 4);
  return out;
}

}  // namespace

std::vector<std::uint32_t> side_strip_indices(const std::vector<ShadowVertex>& sides) {
  const std::size_t quads = sides.size() / 6;
  // Quad q: v0 = (D,1) at 6q, v1 = (A,1) at 6q+1, v2 = (A,0) at 6q+2, v3 = (D,0) at 6q+5.
  std::map<std::array<std::uint32_t, 3>, std::vector<std::size_t>> by_a;
  std::map<std::array<std::uint32_t, 3>, std::size_t> d_count;
  for (std::size_t q = 0; q < quads; ++q) {
    by_a[bits(sides[6 * q + 1])].push_back(q);
    ++d_count[bits(sides[6 * q])];
  }
  std::vector<bool> used(quads, false);
  std::vector<std::uint32_t> out;
  out.reserve(4 * quads);
  auto chain_from = [&](std::size_t q) {
    if (!out.empty()) out.push_back(kStripRestart);
    out.push_back(static_cast<std::uint32_t>(6 * q + 1));
    out.push_back(static_cast<std::uint32_t>(6 * q + 2));
    for (;;) {
      used[q] = true;
      out.push_back(static_cast<std::uint32_t>(6 * q));
      out.push_back(static_cast<std::uint32_t>(6 * q + 5));
      const auto next = by_a.find(bits(sides[6 * q]));
      if (next == by_a.end()) return;
      std::size_t found = quads;
      for (std::size_t n : next->second)
        if (!used[n]) {
          found = n;
          break;
        }
      if (found == quads) return;
      q = found;
    }
  };
  // Open chains from their first quad (whose A is no quad's D), then the loops.
  for (std::size_t q = 0; q < quads; ++q)
    if (!used[q] && d_count.find(bits(sides[6 * q + 1])) == d_count.end()) chain_from(q);
  for (std::size_t q = 0; q < quads; ++q)
    if (!used[q]) chain_from(q);
  return out;
}

ShadowVolumeGeometry shadow_volume_geometry(const TriangleMesh& mesh, const EngineSilhouette& silhouette) {
  ShadowVolumeGeometry g;
  // Each array allocated once at its size (grown by doubling, the arrays of
  // every frame leave freed blocks of every size behind in the heap).
  std::size_t fronts = 0, corrective = 0;
  for (FaceIndex f = 0; f < mesh.triangle_count(); ++f) fronts += silhouette.facing[f] == Facing::Front ? 1 : 0;
  for (QuadCase c : silhouette.cases) corrective += c == QuadCase::C1 || c == QuadCase::C2 ? 1 : 0;
  const std::size_t backs = mesh.triangle_count() - fronts;
  g.sides.reserve(6 * silhouette.edges.size());
  g.sides_vertex.reserve(6 * silhouette.edges.size());
  g.corrective.reserve(6 * corrective);
  g.light_cap.reserve(3 * fronts);
  g.light_cap_vertex.reserve(3 * fronts);
  g.dark_cap.reserve(3 * backs);
  g.dark_cap_vertex.reserve(3 * backs);
  for (std::size_t k = 0; k < silhouette.edges.size(); ++k) {
    const Vec3d& a = mesh.positions[silhouette.edges[k].a];
    const Vec3d& d = mesh.positions[silhouette.edges[k].d];
    add_quad(g.sides, at(d, 1), at(a, 1), at(a, 0), at(d, 0));
    const VertexIndex ia = silhouette.edges[k].a, id = silhouette.edges[k].d;
    g.sides_vertex.insert(g.sides_vertex.end(), {id, ia, ia, id, ia, id});
    if (silhouette.cases[k] == QuadCase::C1) add_quad(g.corrective, at(a, 2), at(a, 1), at(d, 1), at(d, 2));
    if (silhouette.cases[k] == QuadCase::C2) add_quad(g.corrective, at(a, 0), at(a, 4), at(d, 4), at(d, 0));
  }
  for (FaceIndex f = 0; f < mesh.triangle_count(); ++f) {
    const bool front = silhouette.facing[f] == Facing::Front;
    auto& cap = front ? g.light_cap : g.dark_cap;
    auto& index = front ? g.light_cap_vertex : g.dark_cap_vertex;
    for (VertexIndex v : mesh.triangles[f]) {
      cap.push_back(at(mesh.positions[v], front ? 1.0f : 0.0f));
      index.push_back(v);
    }
  }
  return g;
}

}  // namespace nearcap::gl
