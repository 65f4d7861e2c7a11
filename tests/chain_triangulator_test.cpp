// The cap triangulator (src/gl/chain_triangulator.hpp), step by step on
// small hand-made chains: the crossing split, ears, the bridge, the detour
// and the anchor choice, each with the triangles or boundary it must give;
// then the whole cap on random self-crossing chains through infinity
// against the plain fan, pixel by pixel, with the ears' gate forced open.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <vector>

#include "../src/gl/chain_triangulator.hpp"
#include "nearcap/error.hpp"
#include "nearcap/gl/near_plane_cap.hpp"
#include "nearcap/gl/pipeline.hpp"
#include "support/cap_draw_state.hpp"

namespace nearcap {
namespace {

using gl::Vec4f;
namespace chain = gl::chain;

constexpr float kZ = -1.0f;  // the near plane's z at w = 1 (standard depth mapping)

Vec4f at(float x, float y, float w = 1.0f) { return {x * w, y * w, kZ * w, w}; }

bool same_bits(const Vec4f& a, const Vec4f& b) { return std::memcmp(&a, &b, sizeof(Vec4f)) == 0; }

// The chain of a polygon's vertices: 2 vertices per edge, closed.
std::vector<Vec4f> chain_of(const std::vector<Vec4f>& polygon) {
  std::vector<Vec4f> edges;
  for (std::size_t k = 0; k < polygon.size(); ++k)
    edges.insert(edges.end(), {polygon[k], polygon[(k + 1) % polygon.size()]});
  return edges;
}

// Directed edges with multiplicities, an edge and its reverse cancelling,
// vertices matched bit for bit: the boundary the counts depend on.
using Key = std::array<std::uint32_t, 8>;
Key key(const Vec4f& a, const Vec4f& b) {
  Key k;
  std::memcpy(k.data(), &a, sizeof(Vec4f));
  std::memcpy(k.data() + 4, &b, sizeof(Vec4f));
  return k;
}
void add_edge(std::map<Key, int>& boundary, const Vec4f& a, const Vec4f& b, int times) {
  if (same_bits(a, b)) return;
  const Key forward = key(a, b), backward = key(b, a);
  if (forward < backward) {
    if ((boundary[forward] += times) == 0) boundary.erase(forward);
  } else if ((boundary[backward] -= times) == 0) {
    boundary.erase(backward);
  }
}
std::map<Key, int> boundary_of_edges(const std::vector<Vec4f>& edges) {
  std::map<Key, int> b;
  for (std::size_t e = 0; e + 1 < edges.size(); e += 2) add_edge(b, edges[e], edges[e + 1], 1);
  return b;
}
std::map<Key, int> boundary_of_triangles(const std::vector<Vec4f>& t) {
  std::map<Key, int> b;
  for (std::size_t k = 0; k + 2 < t.size(); k += 3) {
    add_edge(b, t[k], t[k + 1], 1);
    add_edge(b, t[k + 1], t[k + 2], 1);
    add_edge(b, t[k + 2], t[k], 1);
  }
  return b;
}

struct Drawn {
  std::vector<std::uint8_t> stencil;
  std::uint64_t fragments;
};
Drawn draw(const std::vector<Vec4f>& triangles, int width, int height) {
  gl::Framebuffer fb(width, height, gl::DepthFormat::Fixed24);
  const gl::DrawCounters c = fb.draw(triangles, test::cap_draw_state(), {});
  return {fb.stencil(), c.fragments};
}

TEST(ChainTriangulator, CrossingSplitCutsABowTieAtOneSharedVertex) {
  // (-1/2, -1/2) -> (1/2, 1/2) -> (1/2, -1/2) -> (-1/2, 1/2): its two
  // diagonals cross at the origin.
  const std::vector<Vec4f> bow{at(-0.5f, -0.5f), at(0.5f, 0.5f), at(0.5f, -0.5f), at(-0.5f, 0.5f)};
  std::vector<Vec4f> slivers;
  const auto circles = chain::seifert_circles(bow, at(0, 0), [&](const Vec4f& a, const Vec4f& b, const Vec4f& c) {
    slivers.insert(slivers.end(), {a, b, c});
  });
  const Vec4f x{0.0f, 0.0f, kZ, 1.0f};
  ASSERT_EQ(circles.size(), 2u);
  // Each pass through X leaves by the other pass's way out.
  const std::vector<Vec4f> first{bow[0], x, bow[3]}, second{bow[1], bow[2], x};
  ASSERT_EQ(circles[0].size(), 3u);
  ASSERT_EQ(circles[1].size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_TRUE(same_bits(circles[0][k], first[k])) << k;
    EXPECT_TRUE(same_bits(circles[1][k], second[k])) << k;
  }
  // One sliver per cut edge, (a, b, X), and with the circles the boundary
  // is the bow tie's.
  ASSERT_EQ(slivers.size(), 6u);
  EXPECT_TRUE(same_bits(slivers[0], bow[0]) && same_bits(slivers[1], bow[1]) && same_bits(slivers[2], x));
  EXPECT_TRUE(same_bits(slivers[3], bow[2]) && same_bits(slivers[4], bow[3]) && same_bits(slivers[5], x));
  std::map<Key, int> pieces = boundary_of_triangles(slivers);
  for (const auto& circle : circles)
    for (std::size_t k = 0; k < circle.size(); ++k) add_edge(pieces, circle[k], circle[(k + 1) % circle.size()], 1);
  EXPECT_EQ(pieces, boundary_of_edges(chain_of(bow)));
  // No crossing: the polygon itself, nothing emitted.
  const std::vector<Vec4f> square{at(-0.5f, -0.5f), at(0.5f, -0.5f), at(0.5f, 0.5f), at(-0.5f, 0.5f)};
  std::size_t emitted = 0;
  const auto same =
      chain::seifert_circles(square, at(0, 0), [&](const Vec4f&, const Vec4f&, const Vec4f&) { ++emitted; });
  ASSERT_EQ(same.size(), 1u);
  EXPECT_EQ(same[0].size(), 4u);
  EXPECT_EQ(emitted, 0u);
}

TEST(ChainTriangulator, EarsSkipATriangleThatHoldsAReflexVertex) {
  // A dart, counter-clockwise: the triangle at its tip (P3, P0, P1) holds
  // the reflex vertex P2, so the first ear is at P1, then what is left.
  const std::vector<Vec4f> dart{at(0.0f, 0.8f), at(-0.8f, -0.8f), at(0.0f, -0.2f), at(0.8f, -0.8f)};
  std::vector<Vec4f> t;
  chain::cut_into_ears(dart, at(0.9f, 0.9f), [&](const Vec4f& a, const Vec4f& b, const Vec4f& c) {
    t.insert(t.end(), {a, b, c});
  });
  const std::vector<Vec4f> expected{dart[0], dart[1], dart[2], dart[3], dart[0], dart[2]};
  ASSERT_EQ(t.size(), expected.size());
  for (std::size_t k = 0; k < t.size(); ++k) EXPECT_TRUE(same_bits(t[k], expected[k])) << k;
  EXPECT_EQ(boundary_of_triangles(t), boundary_of_edges(chain_of(dart)));
}

TEST(ChainTriangulator, EarsTileASimplePolygonOnce) {
  // A comb, counter-clockwise, its teeth across the viewport: n - 2
  // triangles of its own vertices, each pixel drawn at most once, with the
  // fan's counts.
  std::vector<Vec4f> comb{at(-0.9f, -0.9f), at(0.9f, -0.9f)};
  for (int tooth = 3; tooth >= 0; --tooth) {
    const float right = -0.9f + 0.45f * tooth + 0.25f, left = right - 0.25f;
    comb.insert(comb.end(), {at(right, 0.9f), at(left, 0.9f)});
    if (tooth > 0) comb.insert(comb.end(), {at(left, -0.6f), at(left - 0.2f, -0.6f)});
  }
  std::vector<Vec4f> t;
  chain::cut_into_ears(comb, at(0, 0), [&](const Vec4f& a, const Vec4f& b, const Vec4f& c) {
    t.insert(t.end(), {a, b, c});
  });
  EXPECT_EQ(t.size(), 3 * (comb.size() - 2));
  for (const Vec4f& v : t)
    EXPECT_NE(std::find_if(comb.begin(), comb.end(), [&](const Vec4f& c) { return same_bits(c, v); }), comb.end());
  EXPECT_EQ(boundary_of_triangles(t), boundary_of_edges(chain_of(comb)));
  const Drawn ears = draw(t, 128, 128), fan = draw(chain::fan_over(chain_of(comb), at(0, 0)), 128, 128);
  EXPECT_EQ(ears.stencil, fan.stencil);
  std::size_t covered = 0;
  for (std::uint8_t c : ears.stencil) covered += c != 0;
  EXPECT_EQ(ears.fragments, covered);
  EXPECT_GT(fan.fragments, covered);
}

TEST(ChainTriangulator, ABridgeJoinsAHoleToTheLayerAroundTheViewport) {
  // A clockwise square (count -1 inside) in a layer of +1 over the viewport.
  const std::vector<Vec4f> hole{at(-0.3f, -0.2f), at(-0.3f, 0.4f), at(0.5f, 0.4f), at(0.5f, -0.2f)};
  const double m = gl::near_plane_cap_margin(64);
  const float b = static_cast<float>(1 + 2 * m);
  const auto merged = chain::layer_with_hole(chain_of(hole), true, m, m, kZ);
  ASSERT_TRUE(merged.has_value());
  // The box from its corner (-b, -b), counter-clockwise, the bridge to the
  // hole's nearest vertex (-0.3, -0.2), the hole from there, and back.
  const std::vector<Vec4f> box{at(-b, -b), at(b, -b), at(b, b), at(-b, b)};
  std::vector<Vec4f> expected = chain_of(box);
  expected.insert(expected.end(), {box[0], hole[0]});
  const std::vector<Vec4f> hole_edges = chain_of(hole);
  expected.insert(expected.end(), hole_edges.begin(), hole_edges.end());
  expected.insert(expected.end(), {hole[0], box[0]});
  ASSERT_EQ(merged->size(), expected.size());
  for (std::size_t k = 0; k < expected.size(); ++k) EXPECT_TRUE(same_bits((*merged)[k], expected[k])) << k;
  // Cut into ears it draws the layer less the hole, each pixel once.
  std::vector<Vec4f> anchors{at(0, 0)};
  double area = 0;
  const auto ears = chain::ear_clipped(*merged, anchors, m, m, area);
  ASSERT_TRUE(ears.has_value());
  const Drawn d = draw(*ears, 64, 64);
  for (int j = 0; j < 64; ++j)
    for (int i = 0; i < 64; ++i) {
      const float x = (i + 0.5f) / 32 - 1, y = (j + 0.5f) / 32 - 1;
      const bool in_hole = x > -0.3f && x < 0.5f && y > -0.2f && y < 0.4f;
      EXPECT_EQ(d.stencil[j * 64 + i], in_hole ? 0 : 1) << i << ", " << j;
    }
  EXPECT_EQ(d.fragments, 64u * 64u - 26u * 19u);
  // A loop whose nearest vertex to (-b, -b), A, lies behind its own edge
  // B -> C: the bridge goes from the next corner, (b, -b), to B.
  const std::vector<Vec4f> shielded{at(-0.5f, -0.5f), at(0.6f, -0.5f), at(0.9f, -2.4f), at(-2.4f, 0.9f),
                                    at(-0.5f, 0.6f)};
  const auto other = chain::layer_with_hole(chain_of(shielded), true, m, m, kZ);
  ASSERT_TRUE(other.has_value());
  ASSERT_GE(other->size(), 10u);
  EXPECT_TRUE(same_bits((*other)[8], box[1]) && same_bits((*other)[9], shielded[2]));
  EXPECT_TRUE(same_bits(other->front(), box[1]));
}

TEST(ChainTriangulator, ADetourGoesRoundTheViewportOnTheRunsOwnSide) {
  // A run far out on the right, from (3, -1/2) round to (3, 1/2): the
  // shortest path back that counts 0 with it passes the box's right-hand
  // corners.
  const double m = gl::near_plane_cap_margin(64);
  const float b = static_cast<float>(1 + 2 * m);
  const std::vector<Vec4f> run{at(3, -0.5f), at(20, -20), at(20, -20), at(20, 20), at(20, 20), at(3, 0.5f)};
  const auto around = chain::detour(run, m, m, kZ);
  ASSERT_TRUE(around.has_value());
  const std::vector<Vec4f> expected{run.front(), at(b, -b), at(b, -b), run.back()};
  ASSERT_EQ(around->size(), expected.size());
  for (std::size_t k = 0; k < expected.size(); ++k) EXPECT_TRUE(same_bits((*around)[k], expected[k])) << k;
  // The run and the detour back count 0 over the viewport.
  std::vector<Vec4f> closed = run;
  for (std::size_t k = around->size(); k >= 2; k -= 2)
    closed.insert(closed.end(), {(*around)[k - 1], (*around)[k - 2]});
  EXPECT_EQ(gl::near_plane_cap_constant_winding(closed, m, m), 0);
  // A run that starts within the margin: no path avoids it.
  EXPECT_FALSE(chain::detour({at(1.05f, 0), at(20, 0), at(20, 0), at(3, 0.5f)}, m, m, kZ).has_value());
}

TEST(ChainTriangulator, TheAnchorIsTheGridPointInTheKernel) {
  // An L, counter-clockwise: its vertices' mean (-2/15, -2/15) lies outside
  // it, and the fan from there draws the missing quarter twice; of the
  // grid, only (-1/2, -1/2) lies in its kernel [-0.9, -0.4]^2, and its fan
  // tiles the L once.
  const std::vector<Vec4f> l{at(-0.9f, -0.9f), at(0.9f, -0.9f), at(0.9f, -0.4f),
                             at(-0.4f, -0.4f), at(-0.4f, 0.9f), at(-0.9f, 0.9f)};
  const std::vector<Vec4f> edges = chain_of(l);
  Vec4f mean = gl::near_plane_cap_anchor(edges);
  const chain::AnchorChoice choice = chain::choose_anchor(edges, mean, kZ);
  EXPECT_TRUE(same_bits(choice.anchor, at(-0.5f, -0.5f)));
  EXPECT_NEAR(choice.area, choice.net, 1e-12);  // double sums of the same areas, no overdraw
  EXPECT_GT(chain::fan_area(edges, mean), choice.area + 0.08);
  // A convex square round its mean: the mean, no search.
  const std::vector<Vec4f> square = chain_of({at(0.2f, 0.1f), at(0.6f, 0.1f), at(0.6f, 0.5f), at(0.2f, 0.5f)});
  mean = gl::near_plane_cap_anchor(square);
  const chain::AnchorChoice kept = chain::choose_anchor(square, mean, kZ);
  EXPECT_TRUE(same_bits(kept.anchor, mean));
}

TEST(ChainTriangulator, TheGateOptionCutsSmallLoopsIntoEarsWithTheFansCounts) {
  // A small C in a 64 x 48 viewport: its best fan draws fewer than 256
  // fragments twice, so by default it is fanned; with the gate open it is
  // cut into ears.  The counts are the fan's either way.
  const std::vector<Vec4f> c = chain_of({at(-0.25f, -0.25f), at(0.25f, -0.25f), at(0.25f, -0.15f), at(-0.15f, -0.15f),
                                         at(-0.15f, 0.15f), at(0.25f, 0.15f), at(0.25f, 0.25f), at(-0.25f, 0.25f)});
  const std::vector<Vec4f> fanned = chain::cap_triangles(c, 64, 48, kZ);
  const std::vector<Vec4f> cut = chain::cap_triangles(c, 64, 48, kZ, {0});
  EXPECT_EQ(fanned.size(), 3 * c.size() / 2);
  EXPECT_EQ(cut.size(), 3 * (c.size() / 2 - 2));
  const Drawn by_fan = draw(fanned, 64, 48), by_ears = draw(cut, 64, 48);
  EXPECT_EQ(by_fan.stencil, by_ears.stencil);
  EXPECT_LT(by_ears.fragments, by_fan.fragments);
}

// Random closed chains of 3 to 14 vertices that cross themselves, some at
// infinity (w = 0: x, y a direction) and some just behind it (w < 0 by a
// rounding's worth, up to 15 2^-20 of |x| + |y|, as the clipper's cuts of the
// near plane leave them: a point of the near plane itself has w > 0),
// through the whole cap with the ears' gate open, and through ear_clipped
// alone: each pixel's count is the plain fan's (near_plane_cap_fan's
// anchor).  Chains that pass well behind the eye are outside this claim:
// the 3-vertex chain (-4, -1/2, w = -1/64), (1.125, 3/16, w = -3/64), NDC
// (-4, -4) at w = 1/64 counts -1 over the viewport by fans from the centre,
// (1/2, 1/2) and (-0.9, 0.9), 0 by ear_clipped's pieces (the production gate,
// 256 fragments, fans it).
RC_GTEST_PROP(ChainTriangulator, EveryCutCountsWhatThePlainFanCounts, ()) {
  const int n = *rc::gen::inRange(3, 15);
  std::vector<Vec4f> polygon;
  for (int k = 0; k < n; ++k) {
    // Coordinates on a grid of 1/16 (coincidences and collinear triples
    // happen), up to 4 viewports out.
    const float x = *rc::gen::inRange(-64, 65) / 16.0f, y = *rc::gen::inRange(-64, 65) / 16.0f;
    const int kind = *rc::gen::inRange(0, 8);
    float w = 1.0f;
    if (kind == 0) w = 0.0f;                                                                  // at infinity
    if (kind == 1) w = -*rc::gen::inRange(1, 16) * 0x1p-20f * (std::fabs(x) + std::fabs(y));  // just behind
    if (kind == 2) w = *rc::gen::inRange(1, 256) / 64.0f;                                     // another w > 0
    if (w != 1.0f && x == 0 && y == 0) continue;                                              // no direction
    polygon.push_back(w > 0 ? at(x, y, w) : Vec4f{x, y, kZ * w, w});
  }
  RC_PRE(polygon.size() >= 3u);
  const std::vector<Vec4f> edges = chain_of(polygon);
  const int width = 48, height = 40;
  // An edge or fan side through x = y = w = 0 (antipodal ends) is no
  // projective segment: the pipeline refuses the plain fan itself there.
  Drawn fan;
  try {
    fan = draw(chain::fan_over(edges, gl::near_plane_cap_anchor(edges)), width, height);
  } catch (const Error&) {
    RC_DISCARD("the plain fan is degenerate");
  }
  const Drawn cap = draw(chain::cap_triangles(edges, width, height, kZ, {0}), width, height);
  RC_ASSERT(cap.stencil == fan.stencil);
  std::vector<Vec4f> anchors{gl::near_plane_cap_anchor(edges), at(0, 0)};
  for (int k = 0; k < 25; ++k) anchors.push_back(at(chain::kAnchorGrid[k % 5], chain::kAnchorGrid[k / 5]));
  const double m = gl::near_plane_cap_margin(width);
  double area = 0;
  const auto ears = chain::ear_clipped(edges, anchors, m, m, area);
  RC_CLASSIFY(ears.has_value(), "cut into ears");
  RC_CLASSIFY(cap.stencil != std::vector<std::uint8_t>(cap.stencil.size(), 0), "counts not all 0");
  if (ears) {
    RC_ASSERT(draw(*ears, width, height).stencil == fan.stencil);
  }
}

}  // namespace
}  // namespace nearcap
