// The coverage estimates (analysis/screen_coverage.hpp) against pixel
// centres counted one by one: triangles inside, across and behind the view
// volume's planes, with vertices at infinity, clipped or depth-clamped; and
// the near-cap of a triangle's shadow volume as the light sees it, bounded
// or running through infinity on the near plane.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "nearcap/analysis/screen_coverage.hpp"

namespace nearcap {
namespace {

using analysis::CameraPoint;
using analysis::ScreenCoverage;
using analysis::ScreenVertex;

Camera test_camera(int width, int height, double near) {
  Camera c;
  c.frustum = {-0.8 * near, 0.8 * near, -0.6 * near, 0.6 * near, near, 100};
  c.width = width;
  c.height = height;
  return c;
}

// The camera-space point on the near plane under pixel (i, j)'s centre.
Vec3d pixel_centre(const Camera& c, int i, int j) {
  const Frustum& f = c.frustum;
  return {f.left + (i + 0.5) / c.width * (f.right - f.left), f.bottom + (j + 0.5) / c.height * (f.top - f.bottom),
          -f.near};
}

double det3(const Vec3d& a, const Vec3d& b, const Vec3d& c) {
  return a.x * (b.y * c.z - b.z * c.y) - a.y * (b.x * c.z - b.z * c.x) + a.z * (b.x * c.y - b.y * c.x);
}

// Pixel centres whose ray from the eye meets the triangle (homogeneous
// vertices, w 1 or 0): beyond the near plane when `near_clipped`, anywhere
// in front of the eye otherwise.  The ray's points are (P, 1 / t), t > 0,
// with P the centre on the near plane (t >= 1 beyond it); the triangle's are
// sum(a_k V_k), a_k >= 0.  With sum(a_k xyz_k) = P, the point is the ray's
// at 1 / t = sum(a_k w_k).
double counted_pixels(const Camera& c, const std::array<CameraPoint, 3>& t, bool near_clipped) {
  const Vec3d a{t[0].x, t[0].y, t[0].z}, b{t[1].x, t[1].y, t[1].z}, d{t[2].x, t[2].y, t[2].z};
  const double m = det3(a, b, d);
  if (m == 0) return 0;
  double count = 0;
  for (int j = 0; j < c.height; ++j)
    for (int i = 0; i < c.width; ++i) {
      const Vec3d p = pixel_centre(c, i, j);
      const double alpha = det3(p, b, d) / m, beta = det3(a, p, d) / m, gamma = det3(a, b, p) / m;
      if (alpha < 0 || beta < 0 || gamma < 0) continue;
      if (near_clipped && alpha * t[0].w + beta * t[1].w + gamma * t[2].w > 1) continue;
      ++count;
    }
  return count;
}

std::array<ScreenVertex, 3> screen(const ScreenCoverage& s, const std::array<CameraPoint, 3>& t) {
  return {s.vertex(t[0]), s.vertex(t[1]), s.vertex(t[2])};
}

TEST(ScreenCoverage, ATriangleInsideCoversItsProjectedArea) {
  const Camera c = test_camera(100, 80, 1);
  const ScreenCoverage s(c);
  // On the plane z = -2 the near rectangle is twice as large: the corners
  // (-0.8, -0.6, -2) ... map to a quarter of the viewport's edge lengths.
  const std::array<CameraPoint, 3> t{{{-0.8, -0.6, -2, 1}, {0.8, -0.6, -2, 1}, {-0.8, 0.6, -2, 1}}};
  const auto v = screen(s, t);
  EXPECT_DOUBLE_EQ(s.pixels(v.data(), 3), 0.5 * 50 * 40);
}

TEST(ScreenCoverage, AQuadAroundTheViewIsTheViewport) {
  const Camera c = test_camera(64, 48, 0.5);
  const ScreenCoverage s(c);
  const std::array<ScreenVertex, 4> q{s.vertex({-50, -50, -3, 1}), s.vertex({50, -50, -3, 1}),
                                      s.vertex({50, 50, -3, 1}), s.vertex({-50, 50, -3, 1})};
  EXPECT_NEAR(s.pixels(q.data(), 4), 64.0 * 48, 1e-6);
  // Wholly behind the eye, or in front of the near plane: nothing.
  const std::array<ScreenVertex, 3> behind{s.vertex({-1, -1, 2, 1}), s.vertex({1, -1, 2, 1}), s.vertex({0, 1, 2, 1})};
  EXPECT_EQ(s.pixels(behind.data(), 3), 0);
  const std::array<ScreenVertex, 3> before{s.vertex({-0.1, -0.1, -0.2, 1}), s.vertex({0.1, -0.1, -0.2, 1}),
                                           s.vertex({0, 0.1, -0.2, 1})};
  EXPECT_EQ(s.pixels(before.data(), 3), 0);
  EXPECT_GT(s.pixels(before.data(), 3, false), 0);  // depth-clamped, it is drawn
}

// Random triangles, points and directions, across every plane: the
// estimate is the count of pixel centres up to the sampling of the edges.
TEST(ScreenCoverage, RandomTrianglesCoverWhatTheirPixelCentresCount) {
  const Camera c = test_camera(40, 30, 0.5);
  const ScreenCoverage s(c);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> xy(-3, 3), z(-4, 1);
  std::bernoulli_distribution at_infinity(0.25);
  int compared = 0, clipped = 0;
  for (int n = 0; n < 300; ++n) {
    std::array<CameraPoint, 3> t;
    for (auto& p : t) p = {xy(rng), xy(rng), z(rng), at_infinity(rng) ? 0.0 : 1.0};
    for (bool near_clipped : {true, false}) {
      const auto v = screen(s, t);
      const double estimate = s.pixels(v.data(), 3, near_clipped);
      const double counted = counted_pixels(c, t, near_clipped);
      // Pixel centres near an edge fall either way.
      EXPECT_NEAR(estimate, counted, 0.03 * counted + 20) << "triangle " << n << (near_clipped ? "" : " depth-clamped");
      ++compared;
      clipped += (v[0].outside | v[1].outside | v[2].outside) && counted > 0 ? 1 : 0;
    }
  }
  EXPECT_GT(clipped, 50);
  EXPECT_EQ(compared, 600);
}

// Is x in the volume: the ray from the light through x meets the triangle at or before x.
bool in_volume(const std::array<Vec3d, 3>& tri, const Vec3d& light, const Vec3d& x) {
  const Vec3d e{x.x - light.x, x.y - light.y, x.z - light.z};
  const Vec3d a{tri[0].x - light.x, tri[0].y - light.y, tri[0].z - light.z};
  const Vec3d b{tri[1].x - light.x, tri[1].y - light.y, tri[1].z - light.z};
  const Vec3d c{tri[2].x - light.x, tri[2].y - light.y, tri[2].z - light.z};
  // e = alpha a + beta b + gamma c: the ray meets the triangle where all
  // three are >= 0, at e / (alpha + beta + gamma), and x is at or beyond it
  // where that sum is >= 1.
  const double m = det3(a, b, c);
  const double alpha = det3(e, b, c) / m, beta = det3(a, e, c) / m, gamma = det3(a, b, e) / m;
  return alpha >= 0 && beta >= 0 && gamma >= 0 && alpha + beta + gamma >= 1;
}

// A triangle occluder, its light-facing side the whole of it: the near-cap
// the light sees (LightView) against the pixel centres of the near plane
// inside its shadow volume, the light behind the eye, beyond the near plane,
// and just in front of it with the occluder at its depth (the section
// running to infinity on the plane).
TEST(LightView, ANearCapIsTheLightFacingFacesSeenFromTheLight) {
  const Camera c = test_camera(320, 240, 1);
  struct Case {
    std::array<Vec3d, 3> tri;
    Vec3d light;
    const char* what;
  };
  const std::vector<Case> cases{
      {{{{-0.5, -0.4, -0.5}, {0.6, -0.3, -1.6}, {0.1, 0.5, -1.2}}}, {0.1, 0.2, 2}, "light behind the eye"},
      {{{{-0.6, -0.4, -2.0}, {0.7, -0.3, -2.5}, {0.1, 0.6, -2.2}}}, {0.2, 0.1, -6}, "light beyond the near plane"},
      {{{{0.05, -0.3, -0.7}, {0.1, 0.3, -1.3}, {0.2, 0.0, -1.1}}}, {0.0, 0.0, -0.9}, "section through infinity"},
      {{{{-0.2, -0.1, -3}, {0.3, -0.2, -3.2}, {0.0, 0.3, -3.4}}}, {0.0, 0.0, 2}, "occluder beyond the near plane"},
  };
  for (const Case& k : cases) {
    const analysis::LightView view(c, k.light);
    const double estimate = view.triangle_pixels(view.vertex(k.tri[0]), view.vertex(k.tri[1]), view.vertex(k.tri[2]));
    double counted = 0;
    for (int j = 0; j < c.height; ++j)
      for (int i = 0; i < c.width; ++i) counted += in_volume(k.tri, k.light, pixel_centre(c, i, j)) ? 1 : 0;
    std::printf("%s: estimated %.1f, counted %.0f\n", k.what, estimate, counted);
    EXPECT_NEAR(estimate, counted, 0.01 * counted + 20) << k.what;
    if (std::string(k.what) == "occluder beyond the near plane") {
      EXPECT_EQ(estimate, 0);
    } else {
      EXPECT_GT(counted, 1000) << k.what;
    }
  }
}

}  // namespace
}  // namespace nearcap
