// The sides as triangle strips along the silhouette's chains
// (gl::side_strip_indices, the paper's layout for ZP+'s sides): the strips'
// triangles are the quads' own, vertex for vertex and winding for winding,
// and on llvmpipe the lit frame draws the same stencil with them as with
// the same triangles listed in the strips' vertex order.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "llvmpipe_fixture.hpp"
#include "nearcap/gl/shadow_volume_geometry.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/render/lit_frame.hpp"

namespace nearcap {
namespace {

using Triangle = std::array<std::array<float, 4>, 3>;

std::array<float, 4> as_array(const gl::ShadowVertex& v) { return {v.x, v.y, v.z, v.w}; }

// The rotation of (a, b, c) that starts at its smallest vertex: the same
// triangle in the same winding compares equal.
Triangle canonical(Triangle t) {
  const auto first = std::min_element(t.begin(), t.end()) - t.begin();
  std::rotate(t.begin(), t.begin() + first, t.end());
  return t;
}

// GL's triangle strips with primitive restart, as index triples in GL's
// vertex order: triangle i of a strip is (s_i, s_i+1, s_i+2) for even i,
// (s_i+1, s_i, s_i+2) for odd i.
std::vector<std::array<std::uint32_t, 3>> strip_triangle_indices(const std::vector<std::uint32_t>& idx) {
  std::vector<std::array<std::uint32_t, 3>> out;
  std::size_t begin = 0;
  for (std::size_t k = 0; k <= idx.size(); ++k) {
    if (k < idx.size() && idx[k] != gl::kStripRestart) continue;
    for (std::size_t i = begin; i + 2 < k; ++i) {
      const bool even = (i - begin) % 2 == 0;
      out.push_back({idx[even ? i : i + 1], idx[even ? i + 1 : i], idx[i + 2]});
    }
    begin = k + 1;
  }
  return out;
}

std::vector<Triangle> strip_triangles(const std::vector<gl::ShadowVertex>& v, const std::vector<std::uint32_t>& idx) {
  std::vector<Triangle> out;
  for (const auto& t : strip_triangle_indices(idx))
    out.push_back({as_array(v[t[0]]), as_array(v[t[1]]), as_array(v[t[2]])});
  return out;
}

std::vector<Triangle> listed_triangles(const std::vector<gl::ShadowVertex>& v) {
  std::vector<Triangle> out;
  for (std::size_t k = 0; k + 2 < v.size(); k += 3)
    out.push_back({as_array(v[k]), as_array(v[k + 1]), as_array(v[k + 2])});
  return out;
}

TEST(SideStrips, TheStripsAreTheQuadsOwnTriangles) {
  std::size_t quads = 0, indices = 0, chains = 0;
  for (const char* name : {"default.json", "near_split.json", "eye_in_shadow.json", "twisted.json", "room.json",
                           "near_cap_bunny_wall.json"}) {
    const Scene scene = load_scene(std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/" + name);
    gl::EmulationSettings settings;
    settings.record_draws = true;
    const gl::ShadowFrame frame = gl::render_shadow_frame(scene, 0, gl::ShadowMethod::ZPass, settings);
    for (const gl::DrawCall& d : frame.draws) {
      if (!d.vertex_stage || d.vertex_stage->part != gl::GeometryPart::Sides) continue;
      SCOPED_TRACE(name);
      const std::vector<gl::ShadowVertex>& sides = d.vertex_stage->inputs;
      const std::vector<std::uint32_t> idx = gl::side_strip_indices(sides);
      std::vector<Triangle> a = strip_triangles(sides, idx), b = listed_triangles(sides);
      for (Triangle& t : a) t = canonical(t);
      for (Triangle& t : b) t = canonical(t);
      std::sort(a.begin(), a.end());
      std::sort(b.begin(), b.end());
      EXPECT_EQ(a, b);
      quads += sides.size() / 6;
      indices += static_cast<std::size_t>(
          std::count_if(idx.begin(), idx.end(), [](std::uint32_t i) { return i != gl::kStripRestart; }));
      chains += 1 + static_cast<std::size_t>(std::count(idx.begin(), idx.end(), gl::kStripRestart));
    }
  }
  std::printf("[ strips   ] %zu quads: %zu strip indices in %zu chains (%zu vertices as triangles)\n", quads, indices,
              chains, 6 * quads);
  ASSERT_GT(quads, 1000u);
  EXPECT_EQ(indices, 2 * quads + 2 * chains);
  EXPECT_LT(chains * 4, quads) << "the silhouettes should chain into long strips";
}

TEST(SideStrips, NoSidesNoStrip) { EXPECT_TRUE(gl::side_strip_indices({}).empty()); }

class SideStripsTest : public test::LlvmpipeTest {};

// The strips' triangles start from other vertices than the listed ones (a
// strip's even triangle (A1 A0 D1) is the listed (D1 A1 A0) rotated), and
// llvmpipe sets up each triangle's depth plane from its first vertex: a
// depth near-tie can fall the other way.  So the strips draw the stencil of
// the same triangles listed in the strips' vertex order, exactly, and the
// listed order's but for at most one pixel a frame (one, on near_split, for
// each method drawing Z-pass sides).
std::vector<gl::Vec4f> in_strip_order(const std::vector<gl::Vec4f>& v, const std::vector<std::uint32_t>& idx) {
  std::vector<gl::Vec4f> out;
  for (const auto& t : strip_triangle_indices(idx)) out.insert(out.end(), {v[t[0]], v[t[1]], v[t[2]]});
  return out;
}

TEST_F(SideStripsTest, TheLitFrameDrawsTheSameStencilWithStrips) {
  std::size_t differ_from_listed = 0, frames = 0;
  for (const char* name : {"near_split.json", "eye_in_shadow.json", "near_cap_bunny_wall.json", "twisted.json"}) {
    const Scene scene = load_scene(std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/" + name);
    for (gl::ShadowMethod m : gl::kAllShadowMethods) {
      SCOPED_TRACE(std::string(name) + ", " + std::string(gl::to_string(m)));
      gl::EmulationSettings settings;
      settings.record_draws = true;
      const gl::ShadowFrame frame = gl::render_shadow_frame(scene, 0, m, settings);
      // The same frame with each sides draw listed in its strips' vertex order.
      gl::ShadowFrame reordered = frame;
      for (gl::DrawCall& d : reordered.draws) {
        if (!d.vertex_stage || d.vertex_stage->part != gl::GeometryPart::Sides) continue;
        const std::vector<std::uint32_t> idx = gl::side_strip_indices(d.vertex_stage->inputs);
        d.clip_vertices = in_strip_order(d.clip_vertices, idx);
        d.vertex_stage.reset();  // drawn as recorded
      }
      render::LitFrameOptions listed, strips, strip_order;
      listed.read_stencils = strips.read_stencils = strip_order.read_stencils = true;
      strips.side_strips = true;
      const render::LitFrame a = render::render_lit_frame(scene, {frame}, settings.depth, listed);
      const render::LitFrame b = render::render_lit_frame(scene, {frame}, settings.depth, strips);
      const render::LitFrame c = render::render_lit_frame(scene, {reordered}, settings.depth, strip_order);
      EXPECT_EQ(b.stencils.at(0), c.stencils.at(0));
      EXPECT_EQ(b.rgb, c.rgb);
      std::size_t differ = 0;
      for (std::size_t p = 0; p < a.stencils.at(0).size(); ++p) differ += a.stencils[0][p] != b.stencils.at(0)[p];
      EXPECT_LE(differ, 1u);
      differ_from_listed += differ;
      ++frames;
    }
  }
  std::printf("[ strips   ] %zu frames: %zu stencil pixels differ from the listed triangles' (vertex order)\n", frames,
              differ_from_listed);
}

}  // namespace
}  // namespace nearcap
