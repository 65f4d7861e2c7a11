// AtomicZP's near-plane condition over a whole occluder
// (analysis/near_rectangle_pyramid.hpp, occluder_clear_of_near_rectangle_pyramid)
// against the same condition by brute force: each vertex placed against the
// near plane and the eye's plane over rationals, each triangle across the
// slab clipped over rationals alone, in the mesh's order.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <string>
#include <vector>

#include "nearcap/analysis/near_rectangle_pyramid.hpp"
#include "nearcap/exact/camera_space.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/scene/scene.hpp"

namespace nearcap {
namespace {

// The brute force's decision, the triangles it reached before the first
// that meets the pyramid (all where none does), those of them across the
// slab, and those of these left to the clip by their vertices' exact sides;
// past that, every triangle across the slab is clipped all the same, and the
// per-triangle filtered decision (triangle_meets_near_rectangle_pyramid by
// vertex indices) is held against the clip on each: `meeting` counts those
// that meet, `disagree` those where the two differ.
struct BruteForce {
  bool clear = true;
  std::size_t reached = 0, tested = 0, clipped = 0, across = 0, meeting = 0, disagree = 0;
};

// The half-spaces of the pyramid that p lies strictly outside of, one bit
// each, over rationals (near_rectangle_pyramid.hpp's six).
unsigned outside_mask(const RationalVec3& p, const Frustum& f) {
  const Rational n(f.near), l(f.left), r(f.right), b(f.bottom), t(f.top);
  const std::array<Rational, 6> value = {
      Rational(n * p.x + l * p.z), Rational(-n * p.x - r * p.z),
      Rational(n * p.y + b * p.z), Rational(-n * p.y - t * p.z),
      Rational(p.z + n),           Rational(-p.z),
  };
  unsigned mask = 0;
  for (unsigned h = 0; h < value.size(); ++h) mask |= sgn(value[h]) < 0 ? 1u << h : 0u;
  return mask;
}

BruteForce brute_force(const CameraSpaceScene& cs, std::size_t o, const Frustum& frustum) {
  const TriangleMesh& mesh = cs.mesh(o);
  std::vector<RationalVec3> p;
  std::vector<int> place;  // 1 beyond the near plane (z < -near), 2 on or behind the eye's plane (z >= 0), else 0
  for (VertexIndex v = 0; v < mesh.positions.size(); ++v) {
    p.push_back(cs.exact_vertex(o, v));
    const Rational& z = p.back().z;
    place.push_back(sgn(Rational(z + Rational(frustum.near))) < 0 ? 1 : sgn(z) >= 0 ? 2 : 0);
  }
  BruteForce out;
  for (const auto& t : mesh.triangles) {
    if (out.clear) ++out.reached;
    if (place[t[0]] != 0 && place[t[1]] == place[t[0]] && place[t[2]] == place[t[0]]) continue;
    if (out.clear) {
      // Left to the clip: no half-space with every vertex outside it, no
      // vertex inside all six.
      const unsigned a = outside_mask(p[t[0]], frustum), b = outside_mask(p[t[1]], frustum),
                     c = outside_mask(p[t[2]], frustum);
      ++out.tested;
      out.clipped += (a & b & c) == 0 && a != 0 && b != 0 && c != 0 ? 1 : 0;
    }
    ++out.across;
    const bool meets = analysis::triangle_meets_near_rectangle_pyramid({p[t[0]], p[t[1]], p[t[2]]}, frustum);
    out.meeting += meets ? 1 : 0;
    out.disagree += analysis::triangle_meets_near_rectangle_pyramid(cs, o, t, frustum) != meets ? 1 : 0;
    if (meets) out.clear = false;
  }
  return out;
}

// bunny.json with the camera looking from `eye` along `forward`, near 0.05
// (the eye close to the surface: near_plane_condition_benchmark.cpp).
Scene bunny_from(const Vec3d& eye, const Vec3d& forward) {
  Scene s = load_scene(std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/bunny.json");
  const Camera& c = s.camera;
  s.camera = look_at_camera(eye, eye + forward, {0, 1, 0}, 60, 0.05, c.frustum.far, c.width, c.height);
  return s;
}

// On bunny.json as drawn (no triangle across the slab), with the eye close
// to the surface looking along it (9,916 triangles across the slab, none
// meeting the pyramid), tilted 20 degrees off it (some triangles left to the
// rational clip), and looking at it (refused at the first triangle that
// meets): the decision, the triangles reached and those tested are the
// brute force's, and so are those left to the clip; on every triangle
// across the slab the per-triangle filtered decision is the clip's.
TEST(NearRectanglePyramid, OccluderClearExactlyAsTheBruteForce) {
  const Scene drawn = load_scene(std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/bunny.json");
  struct Frame {
    const char* name;
    Scene scene;
    bool clear;
  };
  const std::vector<Frame> frames = {
      {"as drawn", drawn, true},
      {"along", bunny_from({-0.379003, 0.347969, -0.0647518}, {-0.891004, -0.39584, -0.222311}), true},
      {"tilted", bunny_from({-0.419463, 0.250054, -0.0834228}, {-0.390441, -0.0339129, 0.920003}), true},
      {"facing", bunny_from({-0.379003, 0.347969, -0.0647518}, {0.453995, -0.77687, -0.436305}), false},
  };
  std::size_t clipped = 0, meeting = 0;
  for (const auto& [name, s, expect_clear] : frames) {
    const CameraSpaceScene cs(s);
    analysis::NearRectanglePyramidWork work;
    const bool clear = analysis::occluder_clear_of_near_rectangle_pyramid(cs, 0, s.camera.frustum, &work);
    const BruteForce brute = brute_force(cs, 0, s.camera.frustum);
    std::printf("bunny %s: clear %d, reached %zu, tested %zu, clipped %zu; across the slab %zu, meeting %zu\n", name,
                clear ? 1 : 0, work.triangles, work.tested, work.clipped, brute.across, brute.meeting);
    EXPECT_EQ(clear, brute.clear) << name;
    EXPECT_EQ(clear, expect_clear) << name;
    if (std::string(name) != "as drawn") {
      EXPECT_GT(work.tested, 0u) << name;
    }
    EXPECT_EQ(work.triangles, brute.reached) << name;
    EXPECT_EQ(work.tested, brute.tested) << name;
    EXPECT_EQ(work.clipped, brute.clipped) << name;
    EXPECT_EQ(brute.disagree, 0u) << name << ": of " << brute.across << " triangles across the slab";
    clipped += work.clipped;
    meeting += brute.meeting;
  }
  EXPECT_GT(clipped, 0u);  // the rational clip was reached
  EXPECT_GT(meeting, 0u);
}

}  // namespace
}  // namespace nearcap
