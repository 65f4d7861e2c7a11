// nearcap/gl/shadow_volume_geometry.hpp — the vertex arrays of one
// light/occluder pair's shadow volume, as an engine builds them on the CPU
// from its float silhouette (engine_classification.hpp).
//
// Triangles, 3 ShadowVertex each, object space, w codes of Figure 7:
//   sides      per silhouette edge E_m = [A, D] (front face's winding): the quad
//              (D,1) (A,1) (A,0) (D,0), outward-facing (the paper's "normal of
//              triangle AD-light points away from the shadow volume" makes this
//              order counter-clockwise seen from outside the volume), split
//              into (v0, v1, v2) and (v0, v2, v3);
//   corrective the paper's corrective quads, split the same way: case C1
//              {(A,2) (A,1) (D,1) (D,2)}, case C2 {(A,0) (A,4) (D,4) (D,0)};
//   light_cap  the light-front-facing triangles, w = 1;
//   dark_cap   the other triangles, w = 0 (extruded to infinity), same winding.
// Beside sides, light_cap and dark_cap, the mesh vertex each of their
// vertices comes from (what a pass that needs a per-vertex value only once
// per mesh vertex indexes by: the clipped-sides near-cap).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "nearcap/gl/engine_classification.hpp"
#include "nearcap/gl/shadow_vertex_programs.hpp"

namespace nearcap::gl {

struct ShadowVolumeGeometry {
  std::vector<ShadowVertex> sides;
  std::vector<ShadowVertex> corrective;
  std::vector<ShadowVertex> light_cap;
  std::vector<ShadowVertex> dark_cap;
  std::vector<VertexIndex> sides_vertex, light_cap_vertex, dark_cap_vertex;
};

ShadowVolumeGeometry shadow_volume_geometry(const TriangleMesh& mesh, const EngineSilhouette& silhouette);

// The sides as triangle strips along the silhouette's chains (the paper's
// vertex layout for ZP+'s sides): indices into `sides` (6 vertices a quad,
// as above), each chain of quads for edges A->D, D->E, ... as
// [A1 A0 D1 D0 E1 E0 ...] (2 indices a quad, 2 more a chain), chains
// separated by kStripRestart (GL_PRIMITIVE_RESTART_FIXED_INDEX).  A quad
// follows another when its A is bit for bit the other's D.  The strip's
// triangles are the quads' own, vertex for vertex and in the same winding:
// (A1 A0 D1) and, odd, GL's (D1 A0 D0).
constexpr std::uint32_t kStripRestart = 0xFFFFFFFFu;
std::vector<std::uint32_t> side_strip_indices(const std::vector<ShadowVertex>& sides);

}  // namespace nearcap::gl
