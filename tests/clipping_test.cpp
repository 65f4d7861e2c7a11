// Homogeneous clipping: what is inside stays, what crosses the near plane is
// cut there, shared edges are cut at the same point from both triangles.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "nearcap/gl/clipping.hpp"

namespace nearcap::gl {
namespace {

TEST(Clipping, TriangleInsideIsUnchanged) {
  const Vec4f a{0, 0, 0, 1}, b{0.5f, 0, 0, 1}, c{0, 0.5f, 0, 1};
  const auto poly = clip_triangle(a, b, c, {});
  ASSERT_EQ(poly.size(), 3u);
  EXPECT_EQ(poly[0].x, a.x);
  EXPECT_EQ(poly[1].x, b.x);
  EXPECT_EQ(poly[2].y, c.y);
}

TEST(Clipping, TriangleBehindTheNearPlaneVanishes) {
  EXPECT_TRUE(clip_triangle({0, 0, -3, 1}, {1, 0, -3, 1}, {0, 1, -3, 1}, {}).empty());
}

TEST(Clipping, CrossingTheNearPlaneCutsThere) {
  // One vertex behind the near plane (z < -w): a quadrilateral, all of whose
  // vertices lie on or inside the near plane up to float rounding.
  const auto poly = clip_triangle({0, 0, 0.5f, 1}, {0.5f, 0, 0.5f, 1}, {0, 0.5f, -3, 1}, {});
  ASSERT_EQ(poly.size(), 4u);
  int on_plane = 0;
  for (const Vec4f& v : poly) {
    EXPECT_GE(v.z + v.w, -1e-6f);
    on_plane += std::fabs(v.z + v.w) <= 1e-6f;
  }
  EXPECT_EQ(on_plane, 2);
}

TEST(Clipping, SharedEdgeIsCutAtTheSamePointFromBothSides) {
  for (bool mesa : {false, true}) {
    // Two triangles sharing edge (p, q), which crosses the near plane, listed
    // in opposite directions: the cut point must be bit-identical (with either clipper).
    ClipSettings settings;
    settings.mesa = mesa;
    const Vec4f p{0.3f, 0.1f, 0.7f, 1.3f}, q{-0.2f, 0.4f, -2.9f, 0.6f};
    const Vec4f r{0.9f, -0.5f, 0.2f, 1.1f}, s{-0.8f, -0.7f, 0.1f, 1.2f};
    const auto first = clip_triangle(p, q, r, settings);
    const auto second = clip_triangle(q, p, s, settings);
    std::vector<Vec4f> cut_first, cut_second;
    for (const Vec4f& v : first)
      if (std::fabs(v.z + v.w) < 1e-5f) cut_first.push_back(v);
    for (const Vec4f& v : second)
      if (std::fabs(v.z + v.w) < 1e-5f) cut_second.push_back(v);
    bool shared = false;
    for (const Vec4f& u : cut_first)
      for (const Vec4f& v : cut_second) shared |= u.x == v.x && u.y == v.y && u.z == v.z && u.w == v.w;
    EXPECT_TRUE(shared) << (mesa ? "mesa" : "inside");
  }
}

// A side of a shadow volume extruded towards a light a million times the
// scene's size away: its third vertex is ~1e6 to 1e8 in clip space.  Cut
// from that vertex, the near plane's point would be a difference of numbers
// 1e7 apart (every digit cancelled: at 1e7, a vertex with w = 0); the
// clipper cuts it from the small outside vertex instead.  Every vertex of
// the result lies in the view volume (guard band 1) and the near plane's
// cut is the double-precision point to within float rounding.
TEST(Clipping, AVertexExtrudedTowardsAFarLightDoesNotCancelTheCut) {
  const Vec4f v0{-0.330681145f, 1.95595551f, 0.694452763f, 0.89445281f};
  const Vec4f v1{-0.514392912f, 1.71115232f, -0.28535527f, -0.085355252f};  // behind the near plane
  for (const Vec4f v2 : {Vec4f{-918558.0f, -8046954.0f, 2813448.0f, 2813448.0f},
                         Vec4f{-9185585.0f, -80469560.0f, 28134488.0f, 28134488.0f}}) {
    ClipSettings settings;
    settings.guard_band = 1;
    const auto poly = clip_triangle(v0, v1, v2, settings);
    ASSERT_GE(poly.size(), 3u) << v2.x;
    for (const Vec4f& v : poly) {
      EXPECT_GT(v.w, 0.0f) << v2.x;
      const float slack = v.w * 1e-5f;
      EXPECT_LE(std::fabs(v.x), v.w + slack) << v.x << " " << v.w << " (v2.x " << v2.x << ")";
      EXPECT_LE(std::fabs(v.y), v.w + slack) << v.y << " " << v.w << " (v2.x " << v2.x << ")";
      EXPECT_GE(v.z + v.w, -slack) << v.z << " " << v.w << " (v2.x " << v2.x << ")";
    }
    // The near plane's cut of edge (v1, v2), in double.
    const double d1 = double(v1.z) + v1.w, d2 = double(v2.z) + v2.w, t = d1 / (d1 - d2);
    const double x = v1.x + t * (double(v2.x) - v1.x), y = v1.y + t * (double(v2.y) - v1.y);
    const double w = v1.w + t * (double(v2.w) - v1.w);
    const auto cut = clip_to_near_plane(v0, v1, v2, DepthMapping::Standard);
    bool found = false;
    for (const Vec4f& v : cut.vertices)
      found |= std::fabs(v.x - x) < 1e-5 && std::fabs(v.y - y) < 1e-5 && std::fabs(v.w - w) < 1e-5;
    EXPECT_TRUE(found) << "the cut of (v1, v2) at (" << x << ", " << y << ", w " << w << ") (v2.x " << v2.x << ")";
  }
}

// Mesa's clipper (draw_pipe_clip.c, 22.3) cuts from the endpoint nearer
// the plane: c + t (o - c), t = d_c / (d_c - d_o), each operation in float32.
TEST(Clipping, MesasClipperCutsFromTheEndpointNearerThePlane) {
  ClipSettings settings;
  settings.mesa = true;
  const Vec4f third{0.9f, -0.5f, 0.2f, 1.1f};
  // Inside nearer (d = 2 against -2.5), then outside nearer (d = 2 against -0.5).
  for (const Vec4f out : {Vec4f{-0.2f, 0.4f, -3.0f, 0.5f}, Vec4f{-0.2f, 0.4f, -1.0f, 0.5f}}) {
    const Vec4f in{0.3f, 0.1f, 0.7f, 1.3f};
    const float d_in = in.z + in.w, d_out = out.z + out.w;
    const bool from_out = -d_out < d_in;
    const Vec4f& c = from_out ? out : in;
    const Vec4f& o = from_out ? in : out;
    const float d_c = from_out ? d_out : d_in, d_o = from_out ? d_in : d_out;
    const float t = d_c / (d_c - d_o);
    const Vec4f expected{c.x + t * (o.x - c.x), c.y + t * (o.y - c.y), c.z + t * (o.z - c.z), c.w + t * (o.w - c.w)};
    bool found = false;
    for (const Vec4f& v : clip_triangle(in, out, third, settings))
      found |= v.x == expected.x && v.y == expected.y && v.z == expected.z && v.w == expected.w;
    EXPECT_TRUE(found) << (from_out ? "from the outside vertex" : "from the inside vertex");
  }
}

// c + t (o - c), t = d_c / (d_c - d_o), each operation in float32: the cut
// of edge (c, o) from c.
Vec4f cut_from(const Vec4f& c, const Vec4f& o, float d_c, float d_o) {
  const float t = d_c / (d_c - d_o);
  return {c.x + t * (o.x - c.x), c.y + t * (o.y - c.y), c.z + t * (o.z - c.z), c.w + t * (o.w - c.w)};
}
bool holds(const std::vector<Vec4f>& polygon, const Vec4f& v) {
  for (const Vec4f& p : polygon)
    if (p.x == v.x && p.y == v.y && p.z == v.z && p.w == v.w) return true;
  return false;
}

// On a tie (the inside and the outside vertex as far from the plane), Mesa's
// clipper cuts from the inside vertex.  The two cuts differ in their bits
// here, so the test tells them apart.
TEST(Clipping, MesasClipperCutsATieFromTheInsideVertex) {
  ClipSettings settings;
  settings.mesa = true;
  const Vec4f in{1e-3f, 0.1f, 0.7f, 1.3f}, out{3.0f, 0.4f, -2.5f, 0.5f}, third{0.9f, -0.5f, 0.2f, 1.1f};
  const float d_in = in.z + in.w, d_out = out.z + out.w;
  ASSERT_EQ(d_in, -d_out);
  const Vec4f inside = cut_from(in, out, d_in, d_out), outside = cut_from(out, in, d_out, d_in);
  ASSERT_FALSE(inside.x == outside.x && inside.y == outside.y && inside.z == outside.z && inside.w == outside.w);
  const std::vector<Vec4f> polygon = clip_triangle(in, out, third, settings);
  EXPECT_TRUE(holds(polygon, inside));
  EXPECT_FALSE(holds(polygon, outside));
}

// The spec clipper cuts from the inside vertex, also when that vertex is far
// larger than the outside one, where it is the nearer the plane (no digit
// cancels then); only an outside vertex nearer the plane is the start.
TEST(Clipping, AHugeInsideVertexNearerThePlaneIsTheCutsStart) {
  const Vec4f in{0.0f, 0.0f, -28134486.0f, 28134488.0f};                         // d = 2
  const Vec4f out_a{0.25f, 1.0f, -5.0f, 2.0f}, out_b{1.0f, 0.25f, -5.0f, 2.0f};  // d = -3
  const float d_in = in.z + in.w, d_out = out_a.z + out_a.w;
  ASSERT_EQ(d_in, 2.0f);
  ASSERT_EQ(d_out, -3.0f);
  const std::vector<Vec4f> polygon = clip_triangle(in, out_a, out_b, {});
  ASSERT_EQ(polygon.size(), 3u);
  for (const Vec4f& out : {out_a, out_b}) {
    const Vec4f inside = cut_from(in, out, d_in, d_out), outside = cut_from(out, in, d_out, d_in);
    ASSERT_FALSE(inside.x == outside.x && inside.y == outside.y && inside.z == outside.z && inside.w == outside.w);
    EXPECT_TRUE(holds(polygon, inside)) << out.x;
  }
}

// Mesa's DIFFERENT_SIGNS (x y <= 0 and x != y) also fires between a vertex
// exactly on the plane and one inside: a near-duplicate vertex the inside
// clipper does not make.
TEST(Clipping, MesasClipperDuplicatesAVertexOnThePlane) {
  const Vec4f on{0.1f, 0.2f, -1.0f, 1.0f}, in{0.3f, -0.1f, 0.2f, 1.2f}, out{-0.2f, 0.1f, -3.0f, 0.5f};
  ClipSettings mesa;
  mesa.mesa = true;
  const std::vector<Vec4f> ours = clip_triangle(on, in, out, {}), theirs = clip_triangle(on, in, out, mesa);
  EXPECT_EQ(ours.size(), 4u);
  EXPECT_EQ(theirs.size(), 5u);
  EXPECT_TRUE(theirs[0].x == on.x && theirs[1].x == on.x && theirs[1].z == on.z && theirs[1].w == on.w);
}

TEST(Clipping, FarPlaneOnlyWhenAsked) {
  const Vec4f a{0, 0, 5, 1}, b{0.1f, 0, 5, 1}, c{0, 0.1f, 5, 1};  // beyond far (z > w)
  EXPECT_TRUE(clip_triangle(a, b, c, {}).empty());
  EXPECT_EQ(clip_triangle(a, b, c, {false, 8192}).size(), 3u);
}

}  // namespace
}  // namespace nearcap::gl
