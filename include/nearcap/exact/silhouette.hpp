// nearcap/exact/silhouette.hpp — silhouette edges of a closed mesh for a light.
//
// A silhouette edge separates a light-front-facing triangle from one that is
// not (back-facing or edge-on).  It is reported as (a, d) in the winding of its
// front-facing triangle, so the shadow-volume side quad (a, d, d + inf*(d - l),
// a + inf*(a - l)) is consistently oriented (ZP+ section 5.1: "AD is oriented so
// that the normal of triangle AD-light points away from the shadow volume").
#pragma once

#include <vector>

#include "nearcap/exact/light_facing.hpp"
#include "nearcap/scene/mesh.hpp"

namespace nearcap {

struct SilhouetteEdge {
  VertexIndex a = 0;  // E_m = [A, D], in the front face's winding
  VertexIndex d = 0;
  FaceIndex front_face = 0;  // the light-front-facing triangle
  FaceIndex other_face = 0;  // the back-facing or edge-on neighbour
};

// Requires mesh.has_adjacency() and a closed mesh (every neighbour defined).
std::vector<SilhouetteEdge> silhouette_edges(const TriangleMesh& mesh, const std::vector<Facing>& facing);

}  // namespace nearcap
