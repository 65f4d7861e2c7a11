// The fixed-point rasterizer: watertight (a tessellated region covers each
// pixel exactly once; a closed mesh covers each pixel as often by front faces
// as by back faces, since every ray that enters it leaves it), facing from the
// snapped area, degenerate triangles dropped.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>
#include <sstream>

#include "nearcap/gl/float_transforms.hpp"
#include "nearcap/gl/rasterizer.hpp"
#include "nearcap/io/mesh_file.hpp"
#include "nearcap/scene/mesh.hpp"

namespace nearcap::gl {
namespace {

TEST(Rasterizer, TessellatedRegionCoversEveryPixelExactlyOnce) {
  for (FillRule rule : {FillRule::TopLeft, FillRule::BottomLeft}) {
    std::mt19937 rng(12345);
    const int W = 64, H = 48, n = 9;
    // A jittered grid of points; a third of them sit exactly on pixel centres
    // or pixel-centre lines, so edges pass through centres.
    std::vector<WindowVertex> grid((n + 1) * (n + 1));
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        float x = 4.0f + 56.0f * i / n, y = 4.0f + 40.0f * j / n;
        if (i > 0 && i < n && j > 0 && j < n) {
          std::uniform_real_distribution<float> jitter(-1.5f, 1.5f);
          x += jitter(rng);
          y += jitter(rng);
          if (rng() % 3 == 0) {
            x = std::floor(x) + 0.5f;
            y = std::floor(y) + 0.5f;
          }
        }
        grid[j * (n + 1) + i] = {x, y, 0.5f};
      }
    std::vector<int> coverage(W * H, 0);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const WindowVertex a = grid[j * (n + 1) + i], b = grid[j * (n + 1) + i + 1];
        const WindowVertex c = grid[(j + 1) * (n + 1) + i + 1], d = grid[(j + 1) * (n + 1) + i];
        for (const auto& tri : {std::array<WindowVertex, 3>{a, b, c}, std::array<WindowVertex, 3>{a, c, d}})
          rasterize_triangle(tri, W, H, {8, rule}, [&](const Fragment& f) { ++coverage[f.y * W + f.x]; });
      }
    // The outer boundary is the axis-aligned rectangle [4, 60] x [4, 44].
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        const float cx = x + 0.5f, cy = y + 0.5f;
        const bool inside = cx > 4 && cx < 60 && cy > 4 && cy < 44;
        if (inside)
          ASSERT_EQ(coverage[y * W + x], 1) << "pixel " << x << " " << y;
        else
          ASSERT_EQ(coverage[y * W + x], 0) << "pixel " << x << " " << y;
      }
  }
}

TEST(Rasterizer, ClosedMeshIsWatertight) {
  // The generated torus seen by a float32 camera: every view ray crosses as
  // many front faces as back faces; a crack or a double hit in either layer
  // breaks that.
  const TriangleMesh torus = parse_off(
      [] {
        std::ifstream in(std::string(NEARCAP_SOURCE_DIR) + "/data/meshes/torus.off");
        std::stringstream ss;
        ss << in.rdbuf();
        return ss.str();
      }(),
      "torus.off");
  const int W = 160, H = 120;
  Frustum fr;
  fr.left = -0.4;
  fr.right = 0.4;
  fr.bottom = -0.3;
  fr.top = 0.3;
  fr.near = 1;
  fr.far = 50;
  Affine3d view;  // camera at (0.1, 0.7, 4) looking down -z, torus tilted by its own coordinates
  view.rows = {{{1, 0, 0, -0.1}, {0, 0.8, -0.6, -0.2}, {0, 0.6, 0.8, -4.1}}};
  const Mat4f mvp = multiply(frustum_matrix(fr), to_mat4f(view));
  std::vector<int> front(W * H, 0), back(W * H, 0);
  for (const auto& t : torus.triangles) {
    std::array<WindowVertex, 3> w;
    for (int k = 0; k < 3; ++k) {
      const Vec3d& p = torus.positions[t[k]];
      const Vec4f c = transform(mvp, {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z), 1});
      ASSERT_GT(c.w, 0.5f);  // in front of the camera: no clipping needed here
      w[k] = {(c.x / c.w + 1) * 0.5f * W, (c.y / c.w + 1) * 0.5f * H, (c.z / c.w + 1) * 0.5f};
    }
    rasterize_triangle(w, W, H, {}, [&](const Fragment& f) { ++(f.front ? front : back)[f.y * W + f.x]; });
  }
  int covered = 0;
  for (int k = 0; k < W * H; ++k) {
    ASSERT_EQ(front[k], back[k]) << "pixel " << k % W << " " << k / W;
    covered += front[k] > 0;
  }
  EXPECT_GT(covered, W * H / 20) << "the torus is in view";
}

TEST(Rasterizer, FacingComesFromTheSnappedArea) {
  int fragments = 0;
  bool front = false;
  const auto count = [&](const Fragment& f) {
    ++fragments;
    front = f.front;
  };
  // Counter-clockwise in window coordinates (y up): front.
  EXPECT_TRUE(rasterize_triangle({{{1, 1, 0}, {9, 1, 0}, {1, 9, 0}}}, 16, 16, {}, count));
  EXPECT_GT(fragments, 0);
  EXPECT_TRUE(front);
  fragments = 0;
  EXPECT_TRUE(rasterize_triangle({{{1, 1, 0}, {1, 9, 0}, {9, 1, 0}}}, 16, 16, {}, count));
  EXPECT_GT(fragments, 0);
  EXPECT_FALSE(front);
  // Collinear after snapping to 1/256 pixel: dropped.
  fragments = 0;
  EXPECT_FALSE(rasterize_triangle({{{1, 1, 0}, {9, 9, 0}, {5, 5.0001f, 0}}}, 16, 16, {}, count));
  EXPECT_EQ(fragments, 0);
}

TEST(Rasterizer, DepthIsInterpolatedAcrossTheTriangle) {
  std::vector<float> depth(16 * 16, -1);
  rasterize_triangle({{{0, 0, 0}, {16, 0, 1}, {0, 16, 0}}}, 16, 16, {},
                     [&](const Fragment& f) { depth[f.y * 16 + f.x] = f.depth; });
  // float32 barycentric interpolation: a few roundings of values up to 1,
  // 2^-24 each; 1e-6 is 16 ulps of 1.
  EXPECT_NEAR(depth[0 * 16 + 0], 0.5f / 16, 1e-6);
  EXPECT_NEAR(depth[0 * 16 + 7], 7.5f / 16, 1e-6);
}

}  // namespace
}  // namespace nearcap::gl
