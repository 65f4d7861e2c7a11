// The fixed-point rasterizer: watertight (a tessellated region covers each
// pixel exactly once; a closed mesh covers each pixel as often by front faces
// as by back faces, since every ray that enters it leaves it), facing from the
// snapped area, degenerate triangles dropped.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
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

// Every pixel centre of the framebuffer tested against the three snapped edge
// functions, with no row spans, bounding box or incremental arithmetic: the
// rasterizer's fragments must be these, in row-major order, on random
// triangles from sub-pixel slivers to ones larger than the framebuffer, with
// vertices on pixel centres and off the framebuffer, and in row bands.
struct BruteFragment {
  int x, y;
  float depth;
  bool front;
};
std::vector<BruteFragment> brute_force_fragments(const std::array<WindowVertex, 3>& v, int width, int height,
                                                 const RasterSettings& settings, int row_begin, int row_end) {
  const std::int64_t one = std::int64_t{1} << settings.subpixel_bits;
  std::array<std::int64_t, 3> x, y;
  std::array<float, 3> z{v[0].z, v[1].z, v[2].z};
  for (int k = 0; k < 3; ++k) {
    x[k] = std::lrintf(v[k].x * static_cast<float>(one));
    y[k] = std::lrintf(v[k].y * static_cast<float>(one));
  }
  std::int64_t area = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]);
  std::vector<BruteFragment> out;
  if (area == 0) return out;
  const bool front = area > 0;
  if (!front) {
    std::swap(x[1], x[2]);
    std::swap(y[1], y[2]);
    std::swap(z[1], z[2]);
    area = -area;
  }
  for (int j = row_begin; j < std::min(row_end, height); ++j)
    for (int i = 0; i < width; ++i) {
      const std::int64_t px = i * one + one / 2, py = j * one + one / 2;
      std::array<std::int64_t, 3> e;
      bool covered = true;
      for (int k = 0; k < 3 && covered; ++k) {
        const int n = (k + 1) % 3;
        const std::int64_t dx = x[n] - x[k], dy = y[n] - y[k];
        e[k] = dx * (py - y[k]) - dy * (px - x[k]);
        const bool included =
            settings.fill_rule == FillRule::TopLeft ? dy < 0 || (dy == 0 && dx < 0) : dy < 0 || (dy == 0 && dx > 0);
        covered = e[k] > 0 || (e[k] == 0 && included);
      }
      if (!covered) continue;
      const double depth =
          (static_cast<double>(e[1]) * z[0] + static_cast<double>(e[2]) * z[1] + static_cast<double>(e[0]) * z[2]) *
          (1.0 / static_cast<double>(area));
      out.push_back({i, j, static_cast<float>(depth), front});
    }
  return out;
}

TEST(Rasterizer, FragmentsAreThoseOfEveryPixelCentreTestedAlone) {
  std::mt19937 rng(2026);
  const int W = 37, H = 29;
  std::size_t fragments = 0, empty = 0;
  for (int trial = 0; trial < 6000; ++trial) {
    // Scales from a tenth of a pixel to twice the framebuffer, centred
    // anywhere from well off the left and bottom to well off the right and top.
    const float scale = std::pow(10.0f, std::uniform_real_distribution<float>(-1.0f, 1.9f)(rng));
    std::uniform_real_distribution<float> centre(-10.0f, 47.0f), offset(-scale, scale);
    const float cx = centre(rng), cy = centre(rng);
    std::array<WindowVertex, 3> v;
    for (WindowVertex& p : v) {
      p = {cx + offset(rng), cy + offset(rng), std::uniform_real_distribution<float>(0.0f, 1.0f)(rng)};
      if (rng() % 4 == 0) p = {std::floor(p.x) + 0.5f, std::floor(p.y) + 0.5f, p.z};  // on a pixel centre
    }
    // 8 sub-pixel bits (llvmpipe's), and 4 and 12 on every third trial each.
    const RasterSettings settings{std::array{8, 4, 12}[trial % 3],
                                  rng() % 2 ? FillRule::TopLeft : FillRule::BottomLeft};
    const int band = static_cast<int>(rng() % 4);  // 0: every row; else rows [8 (band - 1), 8 band + 5)
    const int row_begin = band == 0 ? 0 : 8 * (band - 1), row_end = band == 0 ? H : 8 * band + 5;
    std::vector<BruteFragment> got;
    rasterize_triangle_with(
        v, W, H, settings,
        [&](const Fragment& f) {
          got.push_back({f.x, f.y, f.depth, f.front});
        },
        row_begin, band == 0 ? -1 : row_end);
    const std::vector<BruteFragment> want = brute_force_fragments(v, W, H, settings, row_begin, row_end);
    ASSERT_EQ(got.size(), want.size()) << "trial " << trial;
    for (std::size_t k = 0; k < want.size(); ++k) {
      ASSERT_EQ(got[k].x, want[k].x) << "trial " << trial << ", fragment " << k;
      ASSERT_EQ(got[k].y, want[k].y) << "trial " << trial << ", fragment " << k;
      ASSERT_EQ(got[k].front, want[k].front) << "trial " << trial;
      ASSERT_EQ(std::memcmp(&got[k].depth, &want[k].depth, sizeof(float)), 0) << "trial " << trial;
    }
    fragments += want.size();
    empty += want.empty();
  }
  // Both kinds occur often: triangles that cover no centre and ones that cover many.
  EXPECT_GT(empty, 500u);
  EXPECT_GT(fragments, 100000u);
}

}  // namespace
}  // namespace nearcap::gl
