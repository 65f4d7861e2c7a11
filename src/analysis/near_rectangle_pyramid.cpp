// An occluder triangle against the near-rectangle pyramid, exactly (see
// near_rectangle_pyramid.hpp).
#include "nearcap/analysis/near_rectangle_pyramid.hpp"

#include <cstdint>
#include <vector>

namespace nearcap::analysis {
namespace {

// The half-space a . p + d >= 0 (a and d exact doubles).
struct HalfSpace {
  double ax = 0, ay = 0, az = 0, d = 0;
};

constexpr int kHalfSpaces = 6;

std::array<HalfSpace, kHalfSpaces> half_spaces(const Frustum& f) {
  return {{
      {f.near, 0, f.left, 0},     // x >= left (-z) / near
      {-f.near, 0, -f.right, 0},  // x <= right (-z) / near
      {0, f.near, f.bottom, 0},   // y >= bottom (-z) / near
      {0, -f.near, -f.top, 0},    // y <= top (-z) / near
      {0, 0, 1, f.near},          // on or behind the near plane (towards the eye): z >= -near
      {0, 0, -1, 0},              // on or in front of the eye's plane: z <= 0 (implied by the four sides)
  }};
}

Rational value(const HalfSpace& h, const RationalVec3& p) {
  return Rational(Rational(h.ax) * p.x + Rational(h.ay) * p.y + Rational(h.az) * p.z + Rational(h.d));
}

// Sutherland-Hodgman against one closed half-space, exactly.
std::vector<RationalVec3> clip(const std::vector<RationalVec3>& poly, const HalfSpace& h) {
  std::vector<RationalVec3> out;
  const std::size_t m = poly.size();
  for (std::size_t k = 0; k < m; ++k) {
    const RationalVec3& a = poly[k];
    const RationalVec3& b = poly[(k + 1) % m];
    const Rational va = value(h, a), vb = value(h, b);
    if (sgn(va) >= 0) out.push_back(a);
    if ((sgn(va) >= 0) != (sgn(vb) >= 0)) {
      const Rational t = va / (va - vb);
      out.push_back(a + t * (b - a));
    }
  }
  return out;
}

}  // namespace

bool triangle_meets_near_rectangle_pyramid(const std::array<RationalVec3, 3>& triangle, const Frustum& frustum) {
  std::vector<RationalVec3> poly(triangle.begin(), triangle.end());
  for (const HalfSpace& h : half_spaces(frustum)) {
    poly = clip(poly, h);
    if (poly.empty()) return false;
  }
  return true;
}

namespace {

// The half-spaces of `hs` that vertex v of occluder o lies strictly outside
// of, bit h for hs[h], each side filtered (BoundedDouble, then rationals).
std::uint8_t outside_mask(const CameraSpaceScene& cs, std::size_t o, VertexIndex v,
                          const std::array<HalfSpace, kHalfSpaces>& hs) {
  const BoundedVec3& p = cs.vertex(o, v);
  std::uint8_t mask = 0;
  for (int h = 0; h < kHalfSpaces; ++h) {
    const HalfSpace& s = hs[h];
    const Sign side = filtered_sign(
        Predicate::NearPlaneSide, nullptr,
        [&] {
          return BoundedDouble(s.ax) * p.x + BoundedDouble(s.ay) * p.y + BoundedDouble(s.az) * p.z + BoundedDouble(s.d);
        },
        [&] { return value(s, cs.exact_vertex(o, v)); });
    if (side == Sign::Negative) mask = static_cast<std::uint8_t>(mask | 1u << h);
  }
  return mask;
}

// Triangle (a, b, c) of occluder o against the pyramid, from its vertices'
// outside masks: a triangle with every vertex strictly outside one
// half-space is clear, one with a vertex inside all six meets; the rest are
// clipped exactly (counted in `clipped`).
bool meets(const CameraSpaceScene& cs, std::size_t o, const std::array<VertexIndex, 3>& triangle,
           const std::array<std::uint8_t, 3>& outside, const Frustum& frustum, std::size_t& clipped) {
  if ((outside[0] & outside[1] & outside[2]) != 0) return false;
  if (outside[0] == 0 || outside[1] == 0 || outside[2] == 0) return true;
  ++clipped;
  return triangle_meets_near_rectangle_pyramid(
      {cs.exact_vertex(o, triangle[0]), cs.exact_vertex(o, triangle[1]), cs.exact_vertex(o, triangle[2])}, frustum);
}

}  // namespace

bool triangle_meets_near_rectangle_pyramid(const CameraSpaceScene& cs, std::size_t o,
                                           const std::array<VertexIndex, 3>& triangle, const Frustum& frustum) {
  const std::array<HalfSpace, kHalfSpaces> hs = half_spaces(frustum);
  std::size_t clipped = 0;
  return meets(cs, o, triangle,
               {outside_mask(cs, o, triangle[0], hs), outside_mask(cs, o, triangle[1], hs),
                outside_mask(cs, o, triangle[2], hs)},
               frustum, clipped);
}

bool occluder_clear_of_near_rectangle_pyramid(const CameraSpaceScene& cs, std::size_t o, const Frustum& frustum,
                                              NearRectanglePyramidWork* work) {
  const double near = frustum.near;
  const BoundedDouble minus_near(-near), zero(0.0);
  const std::array<HalfSpace, kHalfSpaces> hs = half_spaces(frustum);
  const TriangleMesh& mesh = cs.mesh(o);
  // Each vertex's place against the slab, and its outside mask (kNoMask until
  // a triangle across the slab needs it), decided once.
  enum : std::uint8_t { kUnknown, kBeyond, kBehind, kAcross };
  constexpr std::uint8_t kNoMask = 0xff;
  std::vector<std::uint8_t> place(mesh.positions.size(), kUnknown);
  std::vector<std::uint8_t> outside(mesh.positions.size(), kNoMask);
  auto place_of = [&](VertexIndex v) {
    if (place[v] != kUnknown) return place[v];
    const Sign beyond = filtered_sign(
        Predicate::NearPlaneSide, nullptr, [&] { return cs.vertex(o, v).z - minus_near; },
        [&] { return Rational(cs.exact_vertex(o, v).z + Rational(near)); });
    if (beyond == Sign::Negative) return place[v] = kBeyond;
    const Sign behind = filtered_sign(
        Predicate::NearPlaneSide, nullptr, [&] { return cs.vertex(o, v).z - zero; },
        [&] { return Rational(cs.exact_vertex(o, v).z); });
    return place[v] = behind == Sign::Negative ? kAcross : kBehind;
  };
  auto outside_of = [&](VertexIndex v) {
    if (outside[v] == kNoMask) outside[v] = outside_mask(cs, o, v, hs);
    return outside[v];
  };
  NearRectanglePyramidWork local;
  NearRectanglePyramidWork& w = work ? *work : local;
  for (const auto& t : mesh.triangles) {
    ++w.triangles;
    const std::uint8_t a = place_of(t[0]);
    if (a != kAcross && place_of(t[1]) == a && place_of(t[2]) == a) continue;
    ++w.tested;
    if (meets(cs, o, t, {outside_of(t[0]), outside_of(t[1]), outside_of(t[2])}, frustum, w.clipped)) return false;
  }
  return true;
}

}  // namespace nearcap::analysis
