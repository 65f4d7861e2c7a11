// nearcap/gl/near_plane_cap.hpp — the near-cap built in camera space from the
// shadow volume's own clipped boundary (LightProjection::ClippedSides): no
// light frustum, no l_near, no case-D switch.
//
// The near-cap must add, at each pixel, the number of shadow volumes that
// contain the point of the near plane seen there (Z-pass misses exactly
// that count).  That number is the winding number, about the pixel, of the
// closed curves in which the near plane cuts the volumes' boundaries (sides,
// light cap, dark cap, outward oriented).  Each boundary triangle clipped
// against the near plane by the clipper's own arithmetic
// (clip_to_near_plane) leaves at most one edge a -> b lying in the plane;
// the near plane closes the clipped volume with a face that runs that edge
// the other way, so the cap is the fan of triangles (anchor, b, a) over all
// such edges from any one anchor point, drawn with +1 for front faces and -1 for back faces and no
// depth test: a stencil-counted polygon fill whose sum at a pixel is that
// winding number.
//
// Why it cannot crack against the sides: an edge a -> b of a side is the
// same clip-space segment, bit for bit, in the side's clipped polygon and in
// its fan triangle; both are cut by the remaining planes (far, guard band)
// with the same arithmetic (the fan skips only the near-side plane:
// DrawState::vertices_on_near_plane), so they reach the rasterizer with the
// same window coordinates and the fill rule gives each pixel on that edge to
// exactly one side of it.  The curves close exactly: a curve vertex is the
// near plane's cut of a boundary edge, interpolated from that edge's inside
// vertex by both triangles that share it.  Where Z-pass's sides are right,
// Z-pass plus this cap is right; the only float error left is where the
// float sides themselves pass a pixel on the other side from the exact ones.
//
// The real GL clips the sides with its own arithmetic, so there the cap and
// the sides agree only as far as the two clippers do (render/ measures it).
#pragma once

#include <optional>
#include <vector>

#include "nearcap/gl/float_transforms.hpp"

namespace nearcap::gl {

// The edges the near plane's clipping leaves of the closed volumes whose
// boundary triangles are `boundary_clip_vertices` (3 clip-space vertices per
// triangle, as the volume's vertex program wrote them: every side, light-cap
// and dark-cap triangle), 2 vertices per edge, each as the cap runs it (the
// clipped triangle's edge a -> b as b, a).
std::vector<Vec4f> near_plane_cap_edges(const std::vector<Vec4f>& boundary_clip_vertices,
                                        DepthMapping mapping = DepthMapping::Standard);

// The fan's anchor.  Any anchor gives the same winding numbers in exact
// arithmetic; the fragments the fan costs depend on it (a convex cap
// around the anchor is tiled once; away from it the fan also draws, with +1
// and -1, the cone from the anchor to the cap), and in float32 it must keep
// the clipper's cuts of the fan at the viewport's edges accurate.  A vertex
// of the curve itself would tile a convex cap without overdraw, but with
// tiny near planes the curve's vertices are ill-conditioned (|x| >> w:
// window coordinates 10^6 viewports away, w known to a few bits), and a fan
// triangle from such a vertex is cut at the viewport's edge pixels away from
// it, leaving its cut edges inside the viewport (measured: 303 more wrong
// pixels on 10,000 hard cases, all with near <= 2^-19).  So the anchor is a
// point of the near plane with w = 1 inside the viewport, where w dominates
// every cut: the mean, in NDC, of the curve's vertices inside the viewport
// (inside the cap when the cap is convex), or the centre (0, 0, -1, 1) when
// none is (z = w = 1 with the reversed depth mapping).  Every function here
// takes the depth mapping (float_transforms.hpp) that says which clip plane
// is the near plane.
Vec4f near_plane_cap_anchor(DepthMapping mapping = DepthMapping::Standard);  // the centre
// for these edges
Vec4f near_plane_cap_anchor(const std::vector<Vec4f>& edges, DepthMapping mapping = DepthMapping::Standard);

// The cap's fan over those edges from near_plane_cap_anchor(edges), 3
// clip-space vertices per triangle (anchor, b, a).
std::vector<Vec4f> near_plane_cap_fan(const std::vector<Vec4f>& boundary_clip_vertices,
                                      DepthMapping mapping = DepthMapping::Standard);

// The same with a given anchor (any point with w > 0).
std::vector<Vec4f> near_plane_cap_fan(const std::vector<Vec4f>& boundary_clip_vertices, const Vec4f& anchor,
                                      DepthMapping mapping = DepthMapping::Standard);

// Where the near plane cuts the volumes only outside the viewport (the
// `twisted` scene: curves 10 to 40 viewports wide around it), the fan draws
// fragments that all cancel: its count is one number over the whole
// viewport.  That number, when no edge comes within the margin (NDC units)
// of the viewport: the winding number of the edges about the viewport's
// centre, counted as the fan from the centre counts it in oriented
// projective space (vertices at infinity, and those the clipper's rounding
// puts just behind it, w < 0, included), by crossings of the half great
// circle y = 0, x > 0 with exact signs (float products are exact in double).
// Otherwise (an edge near the viewport, a vertex on the axis x = y = 0
// outside it) nothing.
std::optional<int> near_plane_cap_constant_winding(const std::vector<Vec4f>& edges, double margin_x, double margin_y);

// The edges split into closed loops (2 vertices per edge, in loop order),
// matching vertices bit for bit; edges that close no loop (none, for the
// edges of closed volumes) come last, together.
std::vector<std::vector<Vec4f>> near_plane_cap_loops(const std::vector<Vec4f>& edges);

// What the near-cap pass draws for a width x height viewport.  The loops'
// winding numbers add up, so each loop is drawn on its own, with an anchor
// of its own inside the viewport (a small loop far from one shared anchor
// would cost two thin wedges across the viewport per edge):
//   - a loop that stays outside the viewport adds its constant winding
//     (near_plane_cap_constant_winding) to a sum c, drawn last as |c|
//     triangles covering the viewport (counter-clockwise when c > 0; none
//     when c is 0, the common case);
//   - every other loop is fanned.  Before that, each run of its edges that
//     stays away from the viewport is replaced by chords where the closed
//     run-and-chords-back has a constant count over the viewport (added to
//     c), halving the run until it does; or, where that count is not 0 and
//     a detour covers less, by a detour through corners of a box around the
//     viewport on the run's own side (count 0: no triangle over the
//     viewport).  The fan's anchor is the mean above or a point of a 5 x 5
//     grid over the viewport, whichever fan covers the least of it
//     (estimated in double: each triangle clipped to the viewport in
//     homogeneous coordinates);
//   - where that fan would still draw 256 fragments or more twice, the loop
//     is cut into triangles of its own vertices instead: split where it
//     crosses itself (at shared new vertices, with sliver triangles that
//     keep the counts), its runs through infinity detoured or fanned apart,
//     then cut ear by ear, so a curve that winds across the viewport is
//     drawn without overdraw where its pieces are simple;
//   - where c is not 0 and a loop counts the other way (a hole in those
//     layers), one layer and that loop are cut as one polygon, with a
//     bridge between them.
// Every triangle's boundary sums with the others' to the loops' edges, so
// each pixel's count is the single fan's (the tests check it on synthetic
// loops, path frames and the hard-case sampler; docs/findings/
// light-projection.md, "Overdraw of the cap's fan", has the fragments it
// draws on the frames where this matters).  The margin (near_plane_cap_margin: a twentieth of the
// viewport plus 8 pixels) keeps the shortcuts away from edges the float
// pipeline might still rasterize inside the viewport (its cuts of
// far-away, ill-conditioned vertices move them): the fan matches a side's
// such edge exactly, a shortcut would not.
std::vector<Vec4f> near_plane_cap_triangles(const std::vector<Vec4f>& boundary_clip_vertices, int width, int height,
                                            DepthMapping mapping = DepthMapping::Standard);
// That margin in NDC units for a viewport `pixels` wide (or high): 2 / 20 + 16 / pixels.
double near_plane_cap_margin(int pixels);

// ZF+ (the paper's section 5.2 alternative, the far-plane counterpart of
// ZP+), built the same way: Z-fail with a finite far plane and no depth
// clamp misses, at each pixel, the count of the volumes that hold the
// far-plane point behind it: the winding number of the curves the far
// plane's clipping stage leaves of the volumes' boundaries.  ZF+'s volumes
// are clipped at the far plane first (DrawState::far_first; the near plane
// then cuts away only the far plane's half behind the eye), so each edge
// (clip_to_far_plane) is bit for bit a face's far edge, and the curves close
// in the oriented projective far plane as the near cap's do.  The edges (as
// the cap closing the clipped volume runs them) and the cap's triangles,
// drawn like the near-cap's (every added vertex at the far plane's z) with
// Z-fail's counts (DrawState::vertices_on_far_plane: no far plane cuts
// them again; the near plane and x, y as the faces').
std::vector<Vec4f> far_plane_cap_edges(const std::vector<Vec4f>& boundary_clip_vertices,
                                       DepthMapping mapping = DepthMapping::Standard);
std::vector<Vec4f> far_plane_cap_triangles(const std::vector<Vec4f>& boundary_clip_vertices, int width, int height,
                                           DepthMapping mapping = DepthMapping::Standard);

// Which side of the near plane (clip z + w; w - z reversed) the points (w = 1) or the
// directions (w = 0) of the object-space box [lo, hi] all lie on, as the
// float32 pipeline computes it: +1 when every vertex program's output for a
// vertex in the box has near_plane_distance > 0, -1 when every one has < 0,
// 0 when some straddle or come within the certified float32 error bound
// (near_plane_cap.cpp derives it: about 6 * 2^-24 of the products'
// magnitude).  The program's input is each coordinate rounded to float
// (points), or the float light `light` subtracted from it in float
// (directions: [lo, hi] then bounds the exact p - light, and the bound
// grows with |light|; with `light` left at 0 the answer for directions is
// certified only for a light at the origin).  A part of a volume (light
// cap: the mesh's points; dark cap: its directions from the light; sides:
// both) whose boxes are all strictly on one side leaves no edge in the near
// plane, so the pass skips it.
int near_plane_side_of_box(const Mat4f& m, const Vec3d& lo, const Vec3d& hi, double w,
                           DepthMapping mapping = DepthMapping::Standard, const Vec3d& light = {});

}  // namespace nearcap::gl
