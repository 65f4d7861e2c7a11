// gl/chain_triangulator.hpp — closed chains of clip-space edges cut into
// triangles with the same boundary (private to gl/; not installed).
//
// The plane caps (near_plane_cap.hpp) are fans over closed chains of edges
// in one clip plane.  A triangle set draws, at every pixel, the fan's count
// exactly when its boundaries sum, as directed edges with bit-for-bit equal
// vertices, to the chains' edges (a fan's count is relative to its anchor's
// antipode, so every piece here also counts 0 there).  Each step below keeps
// that invariant whatever choices it makes; the choices, made on double
// estimates, only change how many fragments the triangles cost.
//
// Units and frames: every vertex is a clip-space Vec4f (x, y, z, w) in the
// plane the chain lies in; a chain is 2 vertices per edge, each edge's end
// bit for bit the next edge's start; vertices with w <= 0 (at or behind
// infinity) and non-finite vertices may occur where stated.  Vertices a
// step adds (anchors, crossings, box corners) have w = 1 and z = `plane_z`.
// `mx`, `my`: the viewport margin in NDC units (near_plane_cap_margin).
//
// The steps are in chain_triangulator.cpp, the viewport estimates they
// choose by in chain_estimates.cpp.
#pragma once

#include <cstddef>
#include <functional>
#include <limits>
#include <optional>
#include <vector>

#include "nearcap/gl/float_transforms.hpp"

namespace nearcap::gl::chain {

// Receives one triangle (3 clip-space vertices, in drawing order).
using EmitTriangle = std::function<void(const Vec4f&, const Vec4f&, const Vec4f&)>;

// ---- viewport proximity and estimates --------------------------------------

// x, y and w finite.
bool finite(const Vec4f& v);

// Does the clip-space edge p -> q (the arc of positive combinations, as the
// clipper interpolates it), or its antipode, come into the NDC box
// |x| <= bx, |y| <= by?
bool edge_meets_box(const Vec4f& p, const Vec4f& q, double bx, double by);

// A point with w > 0 in NDC, in double; twice the signed area of (a, b, c).
struct Ndc {
  double x, y;
};
Ndc ndc(const Vec4f& v);
double orient(const Ndc& a, const Ndc& b, const Ndc& c);
bool opposite_signs(double a, double b);

// The viewport's area (NDC: 4 in all) that triangle (a, b, c) covers where
// w > 0; `signed_area`: that part's signed area, counter-clockwise positive.
double triangle_area_in_viewport(const Vec4f& a, const Vec4f& b, const Vec4f& c, double& signed_area);

// The fan (anchor, e0, e1) over each edge of `edges`.
std::vector<Vec4f> fan_over(const std::vector<Vec4f>& edges, const Vec4f& anchor);

// The viewport's area the fan from `anchor` covers, once per triangle;
// `net`: the signed sum's magnitude; past `limit` it stops counting.
double fan_area(const std::vector<Vec4f>& edges, const Vec4f& anchor, double* net = nullptr,
                double limit = std::numeric_limits<double>::infinity());

// ---- the steps ---------------------------------------------------------------

// Detour: the edges of a path from `run`'s first vertex to its last through
// 1 to 4 corners of the box |x|, |y| <= 1 + 2 margin (w = 1, z = plane_z)
// such that the run and the path back count 0 over the viewport; nothing
// when no such path avoids the margin.
std::optional<std::vector<Vec4f>> detour(const std::vector<Vec4f>& run, double mx, double my, float plane_z);

// Ears: `polygon` (vertices in order, all with w > 0; no repeated closing
// vertex) cut into triangles of its own vertices, an ear at a time, to
// `emit`; the rest fanned from `anchor` where no ear is left or past
// kEarTestBudget vertex-in-triangle tests.  A simple polygon is so
// triangulated with nothing drawn twice.
constexpr std::size_t kEarTestBudget = std::size_t{1} << 20;
void cut_into_ears(const std::vector<Vec4f>& polygon, const Vec4f& anchor, const EmitTriangle& emit);

// Crossing split: `polygon` (vertices in order, all with w > 0) cut at its
// proper self-crossings into closed polygons that do not cross themselves
// (its Seifert circles), returned; each crossing is one new vertex (w = 1,
// z = anchor.z) shared by the two edges, and the sliver triangles that keep
// the counts go to `emit`.  Without a crossing: {polygon}.
std::vector<std::vector<Vec4f>> seifert_circles(const std::vector<Vec4f>& polygon, const Vec4f& anchor,
                                                const EmitTriangle& emit);

// A closed chain cut into triangles of its own vertices: runs with w <= 0
// detoured or fanned from the best of `anchors` (the first is the chain's
// own), the rest split at its crossings and cut into ears.  Nothing when
// the chain has fewer than 3 or more than kMaxEarClippedVertices edges, a
// non-finite vertex, a break, or no vertex with w > 0.  `area`: the
// triangles' total in the viewport (triangle_area_in_viewport).
constexpr std::size_t kMaxEarClippedVertices = 4096;
std::optional<std::vector<Vec4f>> ear_clipped(const std::vector<Vec4f>& loop, const std::vector<Vec4f>& anchors,
                                              double mx, double my, double& area);

// A closed chain with each run of edges away from the viewport (outside
// the margin) replaced by chords or a detour; `constant` gains the count,
// over the viewport, of what was cut off.  A chain that never comes near
// the viewport comes back as it is.
std::vector<Vec4f> shortened_loop(const std::vector<Vec4f>& loop, const Vec4f& anchor, double mx, double my,
                                  float plane_z, int& constant);

// Bridge: one layer of count +1 (`positive`; else -1) over the viewport and
// the closed chain `loop`, as one chain: the box around the viewport, a
// bridge from one of its corners to the loop's nearest vertex with w > 0
// that crosses no edge of the loop, the loop, and the bridge back.  Nothing
// when every corner's bridge crosses it.
std::optional<std::vector<Vec4f>> layer_with_hole(const std::vector<Vec4f>& loop, bool positive, double mx, double my,
                                                  float plane_z);

// Anchor choice: of `mean` and the points of kAnchorGrid (w = 1, z =
// plane_z), the one whose fan over `edges` covers the least of the viewport
// (the grid searched only where the fan from `mean` covers more than 2 % of
// it twice); `area` that fan's fan_area, `net` the region it fills.
struct AnchorChoice {
  Vec4f anchor;
  double area, net;
};
constexpr float kAnchorGrid[5] = {-1.0f + 0x1p-10f, -0.5f, 0.0f, 0.5f, 1.0f - 0x1p-10f};  // x and y, NDC
AnchorChoice choose_anchor(const std::vector<Vec4f>& edges, const Vec4f& mean, float plane_z);

// ---- the whole cap -----------------------------------------------------------

struct CapOptions {
  // A loop is cut into ears (ear_clipped) only where its best single fan
  // draws at least this many fragments twice; 0 opens the gate for every
  // loop (tests).
  double ears_worth_trying = 256;
};

// The cap's triangles over `edges` (any number of closed chains, in any
// order) for a width x height viewport (near_plane_cap_triangles says what
// is drawn and why); every vertex the pass adds at z = plane_z w.
std::vector<Vec4f> cap_triangles(const std::vector<Vec4f>& edges, int width, int height, float plane_z,
                                 const CapOptions& options = {});

}  // namespace nearcap::gl::chain
