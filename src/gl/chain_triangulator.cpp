// Closed chains cut into triangles with the same boundary (see
// chain_triangulator.hpp): every step below replaces edges by triangles
// whose boundaries, with what is left, sum to those edges, so the counts are
// the fan's whatever the double-precision estimates choose.
#include "chain_triangulator.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "nearcap/gl/clipping.hpp"
#include "nearcap/gl/near_plane_cap.hpp"

namespace nearcap::gl::chain {

// A path around the viewport in place of a whole run of edges away from it:
// from the run's first vertex u to its last v through 1 to 4 corners of the
// box |x|, |y| <= 1 + 2 margin (w = 1, z = plane_z), such that the run and
// the path back count 0 over the viewport.  The fan over it draws the
// wedges of the cap's own side of the viewport, where chords that follow a
// run circling the viewport far away cost wedges all around it, and a chord
// past its other side |count| triangles over all of it (`fly_around` frame
// 38: 34,468 fragments where the cap covers 5,420 pixels).  The count of
// the run with a candidate path back is computed once in full
// (near_plane_cap_constant_winding); the others' from it and the small
// closed polygon of the two paths.  Nothing when no path avoids the margin.
std::optional<std::vector<Vec4f>> detour(const std::vector<Vec4f>& run, double mx, double my, float plane_z) {
  const Vec4f u = run.front(), v = run.back();
  const float bx = static_cast<float>(1 + 2 * mx), by = static_cast<float>(1 + 2 * my);
  const std::array<Vec4f, 4> corner{Vec4f{-bx, -by, plane_z, 1.0f}, Vec4f{bx, -by, plane_z, 1.0f},
                                    Vec4f{bx, by, plane_z, 1.0f}, Vec4f{-bx, by, plane_z, 1.0f}};
  auto backwards = [](const std::vector<Vec4f>& path, std::vector<Vec4f>& edges) {
    for (std::size_t k = path.size() - 1; k > 0; --k) edges.insert(edges.end(), {path[k], path[k - 1]});
  };
  std::optional<std::vector<Vec4f>> base;  // a path whose count with the run is known
  int base_count = 0;
  for (int count = 1; count <= 4; ++count)
    for (int first = 0; first < 4; ++first)
      for (int step : {1, 3}) {  // counter-clockwise, clockwise
        std::vector<Vec4f> path{u};
        for (int k = 0; k < count; ++k) path.push_back(corner[(first + k * step) % 4]);
        path.push_back(v);
        std::optional<int> c;
        if (!base) {
          std::vector<Vec4f> closed = run;
          backwards(path, closed);
          c = near_plane_cap_constant_winding(closed, mx, my);
          if (c) {
            base = path;
            base_count = *c;
          }
        } else {
          std::vector<Vec4f> closed;
          for (std::size_t k = 0; k + 1 < base->size(); ++k) closed.insert(closed.end(), {(*base)[k], (*base)[k + 1]});
          backwards(path, closed);
          if (const std::optional<int> between = near_plane_cap_constant_winding(closed, mx, my))
            c = base_count + *between;
        }
        if (!c || *c != 0) continue;
        std::vector<Vec4f> edges;
        for (std::size_t k = 0; k + 1 < path.size(); ++k) edges.insert(edges.end(), {path[k], path[k + 1]});
        return edges;
      }
  return std::nullopt;
}

// A polygon cut into triangles of its own vertices (all with w > 0), an ear
// at a time: each triangle (a, v, b) of consecutive vertices taken off
// leaves the polygon with the edge a -> b in place of a -> v -> b, so the
// triangles' boundaries and what is left sum to its edges, whatever the
// choices (made in double, in the w > 0 chart: a vertex whose triangle turns
// the polygon's way and holds no other vertex, of which only a reflex one
// can be in it).  A simple polygon is so triangulated: nothing drawn twice.
// Where no ear is left, or past kEarTestBudget tests of a vertex against
// a triangle (a bound on the time), the rest is fanned from `anchor` (w > 0).
void cut_into_ears(const std::vector<Vec4f>& polygon, const Vec4f& anchor, const EmitTriangle& emit) {
  const std::size_t n = polygon.size();
  if (n < 3) return;  // no area: its edges cancel
  std::vector<Ndc> p(n);
  for (std::size_t e = 0; e < n; ++e) p[e] = ndc(polygon[e]);
  auto cross = [&](std::size_t a, std::size_t b, std::size_t c) { return orient(p[a], p[b], p[c]); };
  double twice_area = 0;
  for (std::size_t e = 0; e < n; ++e) {
    const Ndc &u = p[e], &v = p[(e + 1) % n];
    twice_area += u.x * v.y - u.y * v.x;
  }
  const double turn = twice_area < 0 ? -1.0 : 1.0;
  std::vector<std::size_t> prev(n), next(n);
  for (std::size_t e = 0; e < n; ++e) {
    prev[e] = (e + n - 1) % n;
    next[e] = (e + 1) % n;
  }
  std::vector<bool> removed(n, false), reflex(n, false);
  std::vector<std::size_t> reflex_list;
  auto classify = [&](std::size_t v) {
    const bool r = cross(prev[v], v, next[v]) * turn < 0;
    if (r && !reflex[v]) reflex_list.push_back(v);
    reflex[v] = r;
  };
  for (std::size_t v = 0; v < n; ++v) classify(v);
  auto same = [&](std::size_t a, std::size_t b) { return p[a].x == p[b].x && p[a].y == p[b].y; };
  std::size_t budget = kEarTestBudget;
  auto is_ear = [&](std::size_t v) {
    const std::size_t a = prev[v], b = next[v];
    const double t = cross(a, v, b) * turn;
    if (t < 0) return false;
    if (t == 0) return true;  // nothing to draw
    for (std::size_t r : reflex_list) {
      if (budget == 0) return false;
      --budget;
      if (removed[r] || !reflex[r] || r == a || r == v || r == b || same(r, a) || same(r, v) || same(r, b)) continue;
      // Inside or on the triangle (a, v, b) counts as in it.
      if (cross(a, v, r) * turn >= 0 && cross(v, b, r) * turn >= 0 && cross(b, a, r) * turn >= 0) return false;
    }
    return true;
  };
  std::size_t left = n, v = 0, tried = 0;
  while (left > 3 && tried < left) {
    if (!is_ear(v)) {
      v = next[v];
      ++tried;
      continue;
    }
    const std::size_t a = prev[v], b = next[v];
    emit(polygon[a], polygon[v], polygon[b]);
    removed[v] = true;
    next[a] = b;
    prev[b] = a;
    --left;
    classify(a);
    classify(b);
    v = a;
    tried = 0;
  }
  if (left == 3) {
    emit(polygon[prev[v]], polygon[v], polygon[next[v]]);
    return;
  }
  for (std::size_t k = 0; k < left; ++k, v = next[v]) emit(anchor, polygon[v], polygon[next[v]]);
}

// A polygon (all vertices with w > 0) that crosses itself, split into
// polygons that do not (its Seifert circles): each edge cut where another
// crosses it, at one new vertex X (w = 1, z = anchor's z) shared by both,
// and at each X the polygon's two passes reconnected, each coming in to the
// other's way out.  An edge a -> b cut at X_1 .. X_k (in order along it)
// becomes a -> X_1 -> .. -> X_k -> b, and a sliver fan over (a, b, X_k, ..,
// X_1) from a (no wider than the float rounding of X) makes up the
// difference, so the counts stay the polygon's.  The slivers go to `emit`;
// the circles are returned.  Crossings are found in double (proper ones
// only); a choice the rounding gets wrong costs fragments, never a count.
std::vector<std::vector<Vec4f>> seifert_circles(const std::vector<Vec4f>& polygon, const Vec4f& anchor,
                                                const EmitTriangle& emit) {
  const std::size_t n = polygon.size();
  std::vector<Ndc> p(n);
  for (std::size_t e = 0; e < n; ++e) p[e] = ndc(polygon[e]);
  // Edges by their smallest x, each against those that start before it ends.
  std::vector<std::size_t> by_x(n);
  for (std::size_t e = 0; e < n; ++e) by_x[e] = e;
  auto lo = [&](std::size_t e) { return std::min(p[e].x, p[(e + 1) % n].x); };
  auto hi = [&](std::size_t e) { return std::max(p[e].x, p[(e + 1) % n].x); };
  std::sort(by_x.begin(), by_x.end(), [&](std::size_t a, std::size_t b) { return lo(a) < lo(b); });
  struct Cut {
    double t;
    std::size_t vertex;  // index into `extra`
  };
  std::vector<std::vector<Cut>> cuts(n);
  std::vector<Vec4f> extra;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = by_x[k];
    const Ndc &a = p[i], &b = p[(i + 1) % n];
    for (std::size_t m = k + 1; m < n && lo(by_x[m]) <= hi(i); ++m) {
      const std::size_t j = by_x[m];
      if (j == (i + 1) % n || i == (j + 1) % n) continue;
      const Ndc &c = p[j], &d = p[(j + 1) % n];
      if (std::max(c.y, d.y) < std::min(a.y, b.y) || std::max(a.y, b.y) < std::min(c.y, d.y)) continue;
      const double d1 = orient(c, d, a), d2 = orient(c, d, b), d3 = orient(a, b, c), d4 = orient(a, b, d);
      if (!opposite_signs(d1, d2) || !opposite_signs(d3, d4)) continue;  // proper crossings only
      const double t = d1 / (d1 - d2), u = d3 / (d3 - d4);
      const Ndc x{a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)};
      const Vec4f v{static_cast<float>(x.x), static_cast<float>(x.y), anchor.z, 1.0f};
      if (!finite(v)) continue;
      cuts[i].push_back({t, extra.size()});
      cuts[j].push_back({u, extra.size()});
      extra.push_back(v);
    }
  }
  if (extra.empty()) return {polygon};
  // The cut polygon as nodes (vertex, successor); each X's two nodes.
  std::vector<Vec4f> node;
  std::vector<std::array<std::size_t, 2>> at(extra.size(), {n + 2 * extra.size(), 0});
  for (std::size_t e = 0; e < n; ++e) {
    node.push_back(polygon[e]);
    std::sort(cuts[e].begin(), cuts[e].end(), [](const Cut& l, const Cut& r) { return l.t < r.t; });
    for (const Cut& c : cuts[e]) {
      auto& slot = at[c.vertex];
      slot[slot[0] == n + 2 * extra.size() ? 0 : 1] = node.size();
      node.push_back(extra[c.vertex]);
    }
    if (!cuts[e].empty()) {
      const Vec4f &a = polygon[e], &b = polygon[(e + 1) % n];
      emit(a, b, extra[cuts[e].back().vertex]);
      for (std::size_t k = cuts[e].size() - 1; k > 0; --k)
        emit(a, extra[cuts[e][k].vertex], extra[cuts[e][k - 1].vertex]);
    }
  }
  const std::size_t count = node.size();
  std::vector<std::size_t> succ(count);
  for (std::size_t k = 0; k < count; ++k) succ[k] = (k + 1) % count;
  for (const auto& slot : at) std::swap(succ[slot[0]], succ[slot[1]]);
  std::vector<std::vector<Vec4f>> circles;
  std::vector<bool> seen(count, false);
  for (std::size_t k = 0; k < count; ++k) {
    if (seen[k]) continue;
    std::vector<Vec4f>& circle = circles.emplace_back();
    for (std::size_t v = k; !seen[v]; v = succ[v]) {
      seen[v] = true;
      circle.push_back(node[v]);
    }
  }
  return circles;
}

// The loop cut into triangles of its own vertices (cut_into_ears), after
// it is split where it crosses itself (seifert_circles).  A run of vertices
// at or behind infinity (w <= 0), between vertices u and v with w > 0, gives
// way to a detour around the viewport from u to v where one counts 0 with
// it there (detour: nothing of it is drawn); else it is fanned, with the
// chord v -> u closing it, from whichever of `anchors` (w = 1; the first is
// the loop's own) covers the least of the viewport, and the rest of the
// loop takes the chord u -> v: the two chords' triangles cancel.  Every
// piece so counts 0 at the anchors' antipodes, as the fan does, and the
// pieces' boundaries sum to the loop's edges: the counts are the fan's.
// The loop must be a chain of finite vertices (each edge's end bit for bit
// the next one's start) with a vertex with w > 0; else, or past
// kMaxEarClippedVertices, nothing.  `area`: the triangles' total in the
// viewport (triangle_area_in_viewport).
std::optional<std::vector<Vec4f>> ear_clipped(const std::vector<Vec4f>& loop, const std::vector<Vec4f>& anchors,
                                              double mx, double my, double& area) {
  const Vec4f& anchor = anchors.front();
  const std::size_t n = loop.size() / 2;
  if (n < 3 || n > kMaxEarClippedVertices) return std::nullopt;
  std::size_t first_ahead = n;  // a vertex with w > 0
  for (std::size_t e = 0; e < n; ++e) {
    const Vec4f& v = loop[2 * e];
    if (!finite(v) || std::memcmp(&loop[2 * ((e + n - 1) % n) + 1], &v, sizeof(Vec4f)) != 0) return std::nullopt;
    if (v.w > 0 && first_ahead == n) first_ahead = e;
  }
  if (first_ahead == n) return std::nullopt;
  std::vector<Vec4f> out;
  out.reserve(3 * n);
  area = 0;
  auto emit = [&](const Vec4f& a, const Vec4f& b, const Vec4f& c) {
    double unused = 0;
    area += triangle_area_in_viewport(a, b, c, unused);
    out.insert(out.end(), {a, b, c});
  };
  // The vertices with w > 0 in loop order from first_ahead; each run behind
  // them fanned with its chord back.
  std::vector<Vec4f> ahead;
  ahead.reserve(n);
  for (std::size_t k = 0; k < n;) {
    const std::size_t e = (first_ahead + k) % n;
    ahead.push_back(loop[2 * e]);
    std::size_t run = 0;  // vertices behind after e
    while (k + 1 + run < n && !(loop[2 * ((e + 1 + run) % n)].w > 0)) ++run;
    if (run > 0) {
      std::vector<Vec4f> piece;
      for (std::size_t f = 0; f <= run; ++f)
        piece.insert(piece.end(), {loop[2 * ((e + f) % n)], loop[2 * ((e + f) % n) + 1]});
      if (const std::optional<std::vector<Vec4f>> around = detour(piece, mx, my, anchor.z)) {
        for (std::size_t f = 1; f + 1 < around->size(); f += 2) ahead.push_back((*around)[f]);
        k += 1 + run;
        continue;
      }
      piece.insert(piece.end(), {piece.back(), piece.front()});
      const Vec4f* best = &anchors.front();
      double least = fan_area(piece, *best);
      for (const Vec4f& a : anchors) {
        const double a_area = fan_area(piece, a, nullptr, least);
        if (a_area < least) {
          least = a_area;
          best = &a;
        }
      }
      for (std::size_t f = 0; f + 1 < piece.size(); f += 2) emit(*best, piece[f], piece[f + 1]);
    }
    k += 1 + run;
  }
  for (const std::vector<Vec4f>& circle : seifert_circles(ahead, anchor, emit)) cut_into_ears(circle, anchor, emit);
  return out;
}

// Edges [begin, end) of `run` (2 vertices each, consecutive), simplified:
// the chord from the first vertex to the last where the closed
// run-and-chord-back has one count over the viewport
// (near_plane_cap_constant_winding: every edge and the chord away from it),
// that count added to `constant`; else each half the same way.
void simplify_run(const std::vector<Vec4f>& run, std::size_t begin, std::size_t end, double mx, double my,
                  int& constant, std::vector<Vec4f>& out) {
  if (end - begin >= 2) {
    std::vector<Vec4f> closed(run.begin() + 2 * begin, run.begin() + 2 * end);
    const Vec4f u = run[2 * begin], v = run[2 * end - 1];
    closed.insert(closed.end(), {v, u});
    if (const std::optional<int> c = near_plane_cap_constant_winding(closed, mx, my)) {
      constant += *c;
      out.insert(out.end(), {u, v});
      return;
    }
    const std::size_t mid = begin + (end - begin) / 2;
    simplify_run(run, begin, mid, mx, my, constant, out);
    simplify_run(run, mid, end, mx, my, constant, out);
    return;
  }
  out.insert(out.end(), run.begin() + 2 * begin, run.begin() + 2 * end);
}

// A loop that comes into the viewport, with each run of consecutive edges
// that stays away from it simplified (simplify_run): the fan over a run is
// the fan over its chord plus the fan over the closed run-and-chord-back,
// whose count is one number over the viewport.  The loop's edges near the
// viewport, which the sides share bit for bit, are kept as they are.
std::vector<Vec4f> shortened_loop(const std::vector<Vec4f>& loop, const Vec4f& anchor, double mx, double my,
                                  float plane_z, int& constant) {
  const std::size_t n = loop.size() / 2;
  std::vector<bool> far(n);
  std::size_t first_near = n;
  for (std::size_t e = 0; e < n; ++e) {
    far[e] =
        finite(loop[2 * e]) && finite(loop[2 * e + 1]) && !edge_meets_box(loop[2 * e], loop[2 * e + 1], 1 + mx, 1 + my);
    if (!far[e] && first_near == n) first_near = e;
  }
  if (first_near == n) return loop;
  std::vector<Vec4f> out;
  // Walk once around from a near edge, so that no run wraps past the start.
  for (std::size_t k = 0; k < n;) {
    const std::size_t e = (first_near + k) % n;
    if (!far[e]) {
      out.insert(out.end(), {loop[2 * e], loop[2 * e + 1]});
      ++k;
      continue;
    }
    std::vector<Vec4f> run;
    for (; k < n && far[(first_near + k) % n]; ++k) {
      const std::size_t f = (first_near + k) % n;
      run.insert(run.end(), {loop[2 * f], loop[2 * f + 1]});
    }
    // The chords (and their count over the viewport), or a detour around
    // it: whichever the fan covers less of the viewport with.
    std::vector<Vec4f> chords;
    int count = 0;
    simplify_run(run, 0, run.size() / 2, mx, my, count, chords);
    if (count != 0) {
      if (const std::optional<std::vector<Vec4f>> around = detour(run, mx, my, plane_z)) {
        if (fan_area(*around, anchor) < fan_area(chords, anchor) + 4.0 * std::abs(count)) {
          out.insert(out.end(), around->begin(), around->end());
          continue;
        }
      }
    }
    constant += count;
    out.insert(out.end(), chords.begin(), chords.end());
  }
  return out;
}

// One layer of count +1 (`positive`; else -1) over the viewport and a loop
// drawn as one polygon: a box around the viewport (w = 1, corners at 1 + 2
// margins), a bridge from one of its corners to the loop's nearest vertex
// with w > 0, the whole loop from there, and the bridge back.  The bridge's
// two edges cancel, so the polygon counts what the layer and the loop count;
// where the loop is a hole in the layer (its count the layer's opposite) the
// polygon is simple and its ears draw the layer less the hole.  A corner
// whose bridge crosses an edge of the loop (tested in double) is passed
// over; nothing when every one does.
std::optional<std::vector<Vec4f>> layer_with_hole(const std::vector<Vec4f>& loop, bool positive, double mx, double my,
                                                  float plane_z) {
  const float bx = static_cast<float>(1 + 2 * mx), by = static_cast<float>(1 + 2 * my);
  std::array<Vec4f, 4> corner{Vec4f{-bx, -by, plane_z, 1.0f}, Vec4f{bx, -by, plane_z, 1.0f},
                              Vec4f{bx, by, plane_z, 1.0f}, Vec4f{-bx, by, plane_z, 1.0f}};
  if (!positive) std::swap(corner[1], corner[3]);
  const std::size_t n = loop.size() / 2;
  for (std::size_t c = 0; c < 4; ++c) {
    const Ndc from = ndc(corner[c]);
    std::size_t nearest = n;
    double least = std::numeric_limits<double>::infinity();
    for (std::size_t e = 0; e < n; ++e) {
      if (!(loop[2 * e].w > 0)) continue;
      const Ndc v = ndc(loop[2 * e]);
      const double d = (v.x - from.x) * (v.x - from.x) + (v.y - from.y) * (v.y - from.y);
      if (d < least) {
        least = d;
        nearest = e;
      }
    }
    if (nearest == n) return std::nullopt;
    const Ndc to = ndc(loop[2 * nearest]);
    bool crosses = false;
    for (std::size_t e = 0; e < n && !crosses; ++e) {
      const Vec4f &p = loop[2 * e], &q = loop[2 * e + 1];
      if (e == nearest || (e + 1) % n == nearest) continue;
      if (!(p.w > 0) || !(q.w > 0)) continue;  // through infinity: not tested
      const Ndc a = ndc(p), b = ndc(q);
      crosses = opposite_signs(orient(from, to, a), orient(from, to, b)) &&
                opposite_signs(orient(a, b, from), orient(a, b, to));
    }
    if (crosses) continue;
    std::vector<Vec4f> merged;
    for (std::size_t k = 0; k < 4; ++k) merged.insert(merged.end(), {corner[(c + k) % 4], corner[(c + k + 1) % 4]});
    merged.insert(merged.end(), {corner[c], loop[2 * nearest]});
    for (std::size_t k = 0; k < n; ++k)
      merged.insert(merged.end(), {loop[2 * ((nearest + k) % n)], loop[2 * ((nearest + k) % n) + 1]});
    merged.insert(merged.end(), {loop[2 * nearest], corner[c]});
    return merged;
  }
  return std::nullopt;
}

// Any anchor gives the same counts; of the mean and a 5 x 5 grid of points
// of the viewport, all with w = 1 (as well conditioned:
// near_plane_cap_anchor), the one whose fan covers the least of it.  The
// search only where the fan draws more than 2 % of the viewport twice (its
// area beyond the signed sum, the region it fills).
AnchorChoice choose_anchor(const std::vector<Vec4f>& edges, const Vec4f& mean, float plane_z) {
  AnchorChoice choice{mean, 0, 0};
  choice.area = fan_area(edges, mean, &choice.net);
  for (int k = 0; k < 25 && !(choice.area - choice.net < 0.08); ++k) {
    const Vec4f candidate{kAnchorGrid[k % 5], kAnchorGrid[k / 5], plane_z, 1.0f};
    const double area = fan_area(edges, candidate, nullptr, choice.area);  // stops once above the least
    if (area < choice.area) {
      choice.area = area;
      choice.anchor = candidate;
    }
  }
  return choice;
}

// The cap's triangles over `edges` (near_plane_cap_triangles), every vertex
// the pass adds (anchors, the viewport's triangles) at z = plane_z w.
std::vector<Vec4f> cap_triangles(const std::vector<Vec4f>& edges, int width, int height, float plane_z,
                                 const CapOptions& options) {
  const double mx = near_plane_cap_margin(width), my = near_plane_cap_margin(height);
  const double fragments_per_area = 0.25 * width * height;      // NDC area 4: the viewport
  std::vector<Vec4f> anchors{{}, {0.0f, 0.0f, plane_z, 1.0f}};  // [0]: each loop's own
  for (int k = 0; k < 25; ++k)
    if (k != 12) anchors.push_back({kAnchorGrid[k % 5], kAnchorGrid[k / 5], plane_z, 1.0f});
  struct Drawn {
    std::vector<Vec4f> edges, triangles;
    double area;
  };
  std::vector<Drawn> drawn;
  int constant = 0;  // the loops that stay outside the viewport, together
  for (const std::vector<Vec4f>& loop : near_plane_cap_loops(edges)) {
    if (const std::optional<int> c = near_plane_cap_constant_winding(loop, mx, my)) {
      constant += *c;
      continue;
    }
    Vec4f anchor = near_plane_cap_anchor(loop);
    anchor.z = plane_z;
    std::vector<Vec4f> shortened = shortened_loop(loop, anchor, mx, my, plane_z, constant);
    const AnchorChoice choice = choose_anchor(shortened, anchor, plane_z);
    anchor = choice.anchor;
    const double least = choice.area, net = choice.net;
    // Where the best single fan still draws 256 fragments or more twice
    // (its area beyond the region it fills; options.ears_worth_trying): the
    // loop cut into triangles of its own vertices (ear_clipped), where that
    // covers less.  Below that the cut costs more time than it saves.
    if (!((least - net) * fragments_per_area < options.ears_worth_trying)) {
      anchors.front() = anchor;
      double area = 0;
      if (std::optional<std::vector<Vec4f>> ears = ear_clipped(shortened, anchors, mx, my, area);
          ears && area < least) {
        drawn.push_back({std::move(shortened), std::move(*ears), area});
        continue;
      }
    }
    std::vector<Vec4f> fan = fan_over(shortened, anchor);
    drawn.push_back({std::move(shortened), std::move(fan), least});
  }
  // Each loop, while layers over the viewport are left, cut with one of
  // them as one polygon (layer_with_hole) where that covers less than both
  // apart: where the loop is a hole in the layers.
  for (Drawn& d : drawn) {
    if (constant == 0) break;
    if (std::optional<std::vector<Vec4f>> merged = layer_with_hole(d.edges, constant > 0, mx, my, plane_z)) {
      anchors.front() = anchors[1];
      double area = 0;
      if (std::optional<std::vector<Vec4f>> ears = ear_clipped(*merged, anchors, mx, my, area);
          ears && area < d.area + 4.0) {
        d.triangles = std::move(*ears);
        d.area = area;
        constant += constant > 0 ? -1 : 1;
      }
    }
  }
  std::vector<Vec4f> out;
  for (const Drawn& d : drawn) out.insert(out.end(), d.triangles.begin(), d.triangles.end());
  // |constant| triangles over the viewport (the clipper trims them to it).
  const Vec4f a{-1.0f, -1.0f, plane_z, 1.0f}, b{3.0f, -1.0f, plane_z, 1.0f}, d{-1.0f, 3.0f, plane_z, 1.0f};
  for (int k = 0; k < std::abs(constant); ++k) {
    if (constant > 0)
      out.insert(out.end(), {a, b, d});
    else
      out.insert(out.end(), {a, d, b});
  }
  return out;
}

}  // namespace nearcap::gl::chain
