// nearcap/exact/quad_case.hpp — ZP+ section 5: where the near plane cuts a side quad.
//
// The infinite side quad Q of silhouette edge E_m = [A, D] for light l has the
// finite vertices A, D and two vertices at infinity, A_inf (direction A - l)
// and D_inf (direction D - l).  Its edges are E_m = A D, I2 = D D_inf,
// E_inf = D_inf A_inf and I1 = A_inf A.  With the near plane written as
// f(x, w) = x.z + near * w = 0 in homogeneous camera coordinates, a vertex's
// side is sign(f): sign(A.z + near) for A, sign(A.z - l.z) for A_inf.  An edge is
// met exactly when its endpoints lie strictly on opposite sides.  Then:
//   A: no edge met;  B: I1 and I2;  C1: E_m and one of I1, I2;
//   C2: E_inf and one of I1, I2;  D: E_m and E_inf.
// Degenerate: the plane contains a vertex of Q (A or D on the near plane), or
// is parallel to an infinite edge (A_inf or D_inf "on" the plane).  Q is convex
// in the projective plane, so it is met in 0 or 2 edges; four crossings would
// need the light on both sides of the near plane at once.
#pragma once

#include <array>
#include <cstddef>
#include <string_view>

#include "nearcap/exact/camera_space.hpp"
#include "nearcap/exact/silhouette.hpp"

namespace nearcap {

enum class QuadCase : int { A = 0, B, C1, C2, D, Degenerate };
inline constexpr std::size_t kQuadCaseCount = 6;

std::string_view to_string(QuadCase c);  // "A", "B", "C1", "C2", "D", "degenerate"

// Near-plane sides of the quad's four vertices.
struct QuadSides {
  Sign a, d, a_inf, d_inf;
};

// The case from the four sides (Degenerate if any is Zero).
QuadCase quad_case_from_sides(const QuadSides& s);

// Exact sides of the quad of edge (a, d) of object o for light `light`.
QuadSides quad_sides(const CameraSpaceScene& scene, std::size_t o, VertexIndex a, VertexIndex d, std::size_t light,
                     FilterStats* stats);

inline QuadCase quad_case(const CameraSpaceScene& scene, std::size_t o, const SilhouetteEdge& e, std::size_t light,
                          FilterStats* stats) {
  return quad_case_from_sides(quad_sides(scene, o, e.a, e.d, light, stats));
}

}  // namespace nearcap
