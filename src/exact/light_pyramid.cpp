// The largest admissible l_near, exactly (see light_pyramid.hpp).
#include "nearcap/exact/light_pyramid.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "nearcap/error.hpp"

namespace nearcap {
namespace {

// A side plane of the pyramid through l and the rectangle edge from c0 to c1,
// as n . (P - l) >= 0 inside (n oriented towards the rectangle's centre).
template <class T>
struct SidePlane {
  Vec3<T> n;
};

template <class T>
std::array<SidePlane<T>, 4> side_planes(const Vec3<T>& l, const std::array<Vec3<T>, 4>& corners,
                                        const Vec3<T>& centre) {
  std::array<SidePlane<T>, 4> planes;
  for (int k = 0; k < 4; ++k) {
    Vec3<T> n = cross(corners[k] - l, corners[(k + 1) % 4] - l);
    if (dot(n, centre - l) < T(0)) n = T(-1) * n;
    planes[k] = {n};
  }
  return planes;
}

// Sutherland-Hodgman against n . (P - l) >= 0, exactly.
std::vector<RationalVec3> clip(const std::vector<RationalVec3>& poly, const Vec3<Rational>& n, const RationalVec3& l) {
  std::vector<RationalVec3> out;
  const std::size_t m = poly.size();
  for (std::size_t k = 0; k < m; ++k) {
    const RationalVec3& a = poly[k];
    const RationalVec3& b = poly[(k + 1) % m];
    const Rational da = dot(n, a - l), db = dot(n, b - l);
    if (sgn(da) >= 0) out.push_back(a);
    if ((sgn(da) >= 0) != (sgn(db) >= 0)) {
      const Rational t = da / (da - db);
      out.push_back(a + t * (b - a));
    }
  }
  return out;
}

// The pyramid of one (scene, light), exactly and in double: the light, the
// near rectangle's corners and centre, the side planes, alpha and l_far.
struct Pyramid {
  explicit Pyramid(const RationalVec3& light) : l(light) {}
  const RationalVec3& l;
  int alpha = 1;
  Rational ralpha, l_far;
  std::array<SidePlane<Rational>, 4> planes;
  Vec3d ld;                 // the light in double
  std::array<Vec3d, 4> nd;  // the side planes' normals in double
};
Pyramid make_pyramid(const CameraSpaceScene& cs, std::size_t light, const char* what) {
  const Frustum& fr = cs.frustum();
  Pyramid p(cs.exact_light(light));
  const Rational near(fr.near);
  const Rational side = p.l.z + near;
  if (sgn(side) == 0)
    throw Error(ErrorKind::Degenerate,
                std::string("the light lies in the camera's near plane: no ") + what + " (l_far = 0)");
  p.alpha = sgn(side);
  p.ralpha = Rational(p.alpha);
  p.l_far = p.alpha > 0 ? side : Rational(-side);
  const std::array<RationalVec3, 4> corners{RationalVec3{Rational(fr.left), Rational(fr.bottom), -near},
                                            RationalVec3{Rational(fr.right), Rational(fr.bottom), -near},
                                            RationalVec3{Rational(fr.right), Rational(fr.top), -near},
                                            RationalVec3{Rational(fr.left), Rational(fr.top), -near}};
  const RationalVec3 centre{Rational((Rational(fr.left) + Rational(fr.right)) / 2),
                            Rational((Rational(fr.bottom) + Rational(fr.top)) / 2), -near};
  p.planes = side_planes(p.l, corners, centre);
  p.ld = {to_double(p.l.x), to_double(p.l.y), to_double(p.l.z)};
  for (int k = 0; k < 4; ++k)
    p.nd[k] = {to_double(p.planes[k].n.x), to_double(p.planes[k].n.y), to_double(p.planes[k].n.z)};
  return p;
}

}  // namespace

AdmissibleLightNear max_admissible_light_near(const CameraSpaceScene& cs, std::size_t light) {
  const Pyramid pyramid = make_pyramid(cs, light, "light frustum");
  const RationalVec3& l = pyramid.l;
  const int alpha = pyramid.alpha;
  AdmissibleLightNear out;
  out.l_far = pyramid.l_far;
  const Rational& ralpha = pyramid.ralpha;
  auto axial = [&](const RationalVec3& p) { return Rational(ralpha * (l.z - p.z)); };
  const auto& planes = pyramid.planes;
  const Vec3d& ld = pyramid.ld;
  const std::array<Vec3d, 4>& nd = pyramid.nd;

  // Double pass: drop triangles certainly outside one side plane, bound the
  // others' axial distance from below, and sort them by that bound.
  struct Candidate {
    double lower;
    std::size_t object;
    FaceIndex face;
  };
  std::vector<Candidate> candidates;
  for (std::size_t o = 0; o < cs.object_count(); ++o) {
    if (!cs.object(o).occluder) continue;
    const TriangleMesh& mesh = cs.mesh(o);
    const double err = cs.max_error(o);
    for (FaceIndex f = 0; f < mesh.triangles.size(); ++f) {
      const auto& t = mesh.triangles[f];
      std::array<Vec3d, 3> v;
      double mag = std::max({std::fabs(ld.x), std::fabs(ld.y), std::fabs(ld.z)});
      for (int i = 0; i < 3; ++i) {
        v[i] = cs.vertex_estimate(o, t[i]);
        mag = std::max({mag, std::fabs(v[i].x), std::fabs(v[i].y), std::fabs(v[i].z)});
      }
      // A generous bound on the error of n . (v - l) in double: the vertex
      // error, the plane normal's rounding, and the products' rounding.
      bool outside = false;
      for (int k = 0; k < 4 && !outside; ++k) {
        const double nmag = std::fabs(nd[k].x) + std::fabs(nd[k].y) + std::fabs(nd[k].z);
        const double bound = nmag * (3 * err + 2 * mag * 0x1p-40);
        outside = true;
        for (int i = 0; i < 3 && outside; ++i) outside = dot(nd[k], v[i] - ld) < -bound;
      }
      if (outside) continue;
      // Every point of the triangle has axial distance >= the smallest vertex's.
      double lower = std::numeric_limits<double>::infinity();
      for (int i = 0; i < 3; ++i) lower = std::min(lower, alpha * (ld.z - v[i].z));
      candidates.push_back({lower - (2 * err + mag * 0x1p-40), o, f});
    }
  }
  std::sort(candidates.begin(), candidates.end(),
            [](const Candidate& a, const Candidate& b) { return a.lower < b.lower; });

  // Exact pass, nearest first, until no remaining triangle can go lower.
  for (const Candidate& c : candidates) {
    if (out.l_near && c.lower > to_double(*out.l_near) * (1 + 0x1p-40) + 1e-300) break;
    const auto& t = cs.mesh(c.object).triangles[c.face];
    std::vector<RationalVec3> poly{cs.exact_vertex(c.object, t[0]), cs.exact_vertex(c.object, t[1]),
                                   cs.exact_vertex(c.object, t[2])};
    for (const auto& p : planes) {
      poly = clip(poly, p.n, l);
      if (poly.empty()) break;
    }
    ++out.exact_triangles;
    for (const RationalVec3& p : poly) {
      const Rational a = axial(p);
      if (sgn(a) <= 0) continue;  // the apex itself (a triangle through the light): not in the open pyramid
      if (!out.l_near || a < *out.l_near) out.l_near = a;
    }
  }
  return out;
}

std::vector<bool> occluders_meeting_light_pyramid(const CameraSpaceScene& cs, std::size_t light) {
  const Frustum& fr = cs.frustum();
  const Pyramid pyramid = make_pyramid(cs, light, "light pyramid");
  const RationalVec3& l = pyramid.l;
  const int alpha = pyramid.alpha;
  const Rational& l_far = pyramid.l_far;
  const Rational& ralpha = pyramid.ralpha;
  const auto& planes = pyramid.planes;
  const Vec3d& ld = pyramid.ld;
  const double l_far_d = to_double(l_far);
  const std::array<Vec3d, 4>& nd = pyramid.nd;

  const BoundedVec3& light_b = cs.light(light);
  const BoundedVec3 centre_b{(BoundedDouble(fr.left) + BoundedDouble(fr.right)) * BoundedDouble(0.5),
                             (BoundedDouble(fr.bottom) + BoundedDouble(fr.top)) * BoundedDouble(0.5),
                             BoundedDouble(-fr.near)};
  auto certain_sign = [](const BoundedDouble& x) {
    const auto s = x.sign();
    return s ? static_cast<int>(*s) : 0;  // 0: zero or not certain
  };
  auto axis_crosses = [&](const BoundedVec3& a, const BoundedVec3& b, const BoundedVec3& c) {
    const int sl = certain_sign(orientation_determinant(a, b, c, light_b));
    const int sc = certain_sign(orientation_determinant(a, b, c, centre_b));
    if (sl == 0 || sc == 0 || sl == sc) return false;
    const int e1 = certain_sign(orientation_determinant(light_b, centre_b, a, b));
    const int e2 = certain_sign(orientation_determinant(light_b, centre_b, b, c));
    const int e3 = certain_sign(orientation_determinant(light_b, centre_b, c, a));
    return e1 != 0 && e1 == e2 && e2 == e3;
  };

  // The same in plain double, as a prefilter only (it never decides).
  const Vec3d centre_d{centre_b.x.v, centre_b.y.v, centre_b.z.v};
  auto axis_may_cross = [&](const Vec3d& a, const Vec3d& b, const Vec3d& c) {
    const double sl = orientation_determinant(a, b, c, ld), sc = orientation_determinant(a, b, c, centre_d);
    if ((sl > 0) == (sc > 0)) return false;
    const double e1 = orientation_determinant(ld, centre_d, a, b), e2 = orientation_determinant(ld, centre_d, b, c),
                 e3 = orientation_determinant(ld, centre_d, c, a);
    return (e1 > 0) == (e2 > 0) && (e2 > 0) == (e3 > 0);
  };

  std::vector<bool> meets(cs.object_count(), false);
  for (std::size_t o = 0; o < cs.object_count(); ++o) {
    if (!cs.object(o).occluder) continue;
    const TriangleMesh& mesh = cs.mesh(o);
    const double err = cs.max_error(o);
    // Boxes first: an object-space box whose image is certainly outside one
    // side plane, behind the light or beyond the near plane holds no point of
    // the pyramid, and neither do its triangles.  The image of a box's
    // corners through view * object_to_world in double holds the exact image
    // of the box (affine maps keep convex hulls); their rounding is far below
    // the margin added.
    const Affine3d& view = cs.scene().camera.view;
    const Affine3d& model = cs.object(o).object_to_world;
    // Where a box lies: certainly outside, certainly inside (every point of
    // it in the pyramid, the light's own point excluded by the margin), or
    // not decided.
    enum class Where { Outside, Inside, Unknown };
    auto where = [&](const Vec3d& blo, const Vec3d& bhi) {
      Vec3d lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
               std::numeric_limits<double>::infinity()};
      Vec3d hi = -1.0 * lo;
      double corner_mag = 0;
      for (int corner = 0; corner < 8; ++corner) {
        const Vec3d w =
            model.apply({(corner & 1) ? bhi.x : blo.x, (corner & 2) ? bhi.y : blo.y, (corner & 4) ? bhi.z : blo.z});
        const Vec3d p = view.apply(w);
        for (int a = 0; a < 3; ++a) {
          lo[a] = std::min(lo[a], p[a]);
          hi[a] = std::max(hi[a], p[a]);
          corner_mag = std::max({corner_mag, std::fabs(w[a]), std::fabs(p[a])});
        }
      }
      const double box_err = err + 0x1p-30 * corner_mag;
      for (int a = 0; a < 3; ++a) {
        lo[a] -= box_err;
        hi[a] += box_err;
      }
      double mag = std::max({std::fabs(ld.x), std::fabs(ld.y), std::fabs(ld.z), l_far_d});
      for (int a = 0; a < 3; ++a) mag = std::max({mag, std::fabs(lo[a]), std::fabs(hi[a])});
      bool inside = true;
      for (int k = 0; k < 4; ++k) {
        const double nmag = std::fabs(nd[k].x) + std::fabs(nd[k].y) + std::fabs(nd[k].z);
        const double bound = nmag * (3 * err + 2 * mag * 0x1p-40);
        bool outside = true;
        for (int corner = 0; corner < 8; ++corner) {
          const Vec3d p{(corner & 1) ? hi.x : lo.x, (corner & 2) ? hi.y : lo.y, (corner & 4) ? hi.z : lo.z};
          const double signed_distance = dot(nd[k], p - ld);
          outside = outside && signed_distance < -bound;
          inside = inside && signed_distance > bound;
        }
        if (outside) return Where::Outside;
      }
      const double axial_bound = 2 * err + mag * 0x1p-40;
      const double a_lo = alpha > 0 ? ld.z - hi.z : lo.z - ld.z, a_hi = alpha > 0 ? ld.z - lo.z : hi.z - ld.z;
      if (a_hi < -axial_bound || a_lo > l_far_d + axial_bound) return Where::Outside;
      return inside && a_lo > axial_bound && a_hi < l_far_d - axial_bound ? Where::Inside : Where::Unknown;
    };
    const FacePlanes& fp = mesh.face_planes;
    const bool boxed = fp.plane.size() == mesh.triangles.size() && fp.chunk_faces.size() == mesh.triangles.size() &&
                       !mesh.triangles.empty();
    if (boxed) {
      const Where w = where(fp.box_lo, fp.box_hi);
      if (w == Where::Outside) continue;
      if (w == Where::Inside) {
        meets[o] = true;
        continue;
      }
    }
    std::vector<FaceIndex> undecided;
    for (std::size_t slot = 0; slot < mesh.triangles.size() && !meets[o]; ++slot) {
      // Chunk by chunk where the chunks exist, else in file order.
      const std::size_t chunk = slot / FacePlanes::kFacesPerChunk;
      if (boxed && slot % FacePlanes::kFacesPerChunk == 0) {
        const Where w = where(fp.chunk_box[chunk][0], fp.chunk_box[chunk][1]);
        if (w == Where::Inside) {
          meets[o] = true;  // its faces' points all lie in the pyramid
          break;
        }
        if (w == Where::Outside) {
          slot += FacePlanes::kFacesPerChunk - 1;  // the whole chunk is outside
          continue;
        }
      }
      const FaceIndex f = boxed ? fp.chunk_faces[slot] : static_cast<FaceIndex>(slot);
      const auto& t = mesh.triangles[f];
      std::array<Vec3d, 3> v;
      double mag = std::max({std::fabs(ld.x), std::fabs(ld.y), std::fabs(ld.z), l_far_d});
      for (int i = 0; i < 3; ++i) {
        v[i] = cs.vertex_estimate(o, t[i]);
        mag = std::max({mag, std::fabs(v[i].x), std::fabs(v[i].y), std::fabs(v[i].z)});
      }
      // Certainly outside a side plane, behind the light or beyond the near
      // plane (the same generous bounds as above): not in the pyramid.
      // A vertex certainly inside (every side plane, 0 < a <= l_far, with the
      // same bounds): the occluder meets the pyramid, no exact clipping needed.
      bool outside = false;
      std::array<bool, 3> vertex_inside{true, true, true};
      for (int k = 0; k < 4 && !outside; ++k) {
        const double nmag = std::fabs(nd[k].x) + std::fabs(nd[k].y) + std::fabs(nd[k].z);
        const double bound = nmag * (3 * err + 2 * mag * 0x1p-40);
        outside = true;
        for (int i = 0; i < 3; ++i) {
          const double signed_distance = dot(nd[k], v[i] - ld);
          outside = outside && signed_distance < -bound;
          vertex_inside[static_cast<std::size_t>(i)] =
              vertex_inside[static_cast<std::size_t>(i)] && signed_distance > bound;
        }
      }
      const double axial_bound = 2 * err + mag * 0x1p-40;
      bool behind = true, beyond = true;
      for (int i = 0; i < 3; ++i) {
        const double a = alpha * (ld.z - v[i].z);
        behind = behind && a < -axial_bound;
        beyond = beyond && a > l_far_d + axial_bound;
        vertex_inside[static_cast<std::size_t>(i)] =
            vertex_inside[static_cast<std::size_t>(i)] && a > axial_bound && a < l_far_d - axial_bound;
      }
      if (outside || behind || beyond) continue;
      if (vertex_inside[0] || vertex_inside[1] || vertex_inside[2]) {
        meets[o] = true;
        break;
      }
      // The pyramid's axis, from the light to the near rectangle's centre,
      // certainly through the triangle's interior (certified orientations):
      // the crossing point lies in the pyramid.
      if (axis_may_cross(v[0], v[1], v[2]) &&
          axis_crosses(cs.vertex(o, t[0]), cs.vertex(o, t[1]), cs.vertex(o, t[2]))) {
        meets[o] = true;
        break;
      }
      undecided.push_back(f);  // clipped exactly below, if nothing cheaper decides
    }
    // Exact clipping of the triangles no filter decided, until one meets.
    for (std::size_t k = 0; k < undecided.size() && !meets[o]; ++k) {
      const auto& t = mesh.triangles[undecided[k]];
      std::vector<RationalVec3> poly{cs.exact_vertex(o, t[0]), cs.exact_vertex(o, t[1]), cs.exact_vertex(o, t[2])};
      for (const auto& p : planes) {
        poly = clip(poly, p.n, l);
        if (poly.empty()) break;
      }
      // The clipped polygon is convex and the axial distance linear on it:
      // it meets 0 < a <= l_far when its largest a is above 0 and its
      // smallest at most l_far.
      bool above_apex = false, before_far = false;
      for (const RationalVec3& p : poly) {
        const Rational a = ralpha * (l.z - p.z);
        above_apex = above_apex || sgn(a) > 0;
        before_far = before_far || a <= l_far;
      }
      meets[o] = above_apex && before_far;
    }
  }
  return meets;
}

}  // namespace nearcap
