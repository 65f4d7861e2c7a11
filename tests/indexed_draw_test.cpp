// Indexed draws (glDrawElements): the clipper's trivial tests from codes
// computed once per vertex (TriangleClipper::code), and the setup of an
// indexed draw (Framebuffer::set_up with corner indices), which codes,
// divides and snaps each vertex once, give bit for bit what the gathered
// corners give: the same polygons, the same set-up triangles and counters,
// the same refusal of a degenerate vertex.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "nearcap/error.hpp"
#include "nearcap/gl/clipping.hpp"
#include "nearcap/gl/pipeline.hpp"

namespace nearcap::gl {
namespace {

bool same_bits(const std::vector<Vec4f>& a, const std::vector<Vec4f>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec4f)) == 0);
}

// Clip-space vertices inside, outside and across every plane (guard band
// `guard` included: a third within the view volume where w > 0, a third
// within the guard band, a third far outside it), some exactly on one (x =
// guard w, the near or the far plane of `mapping`), some behind the eye,
// the degenerate (0, 0, 0, 0) and a NaN among them when asked.
std::vector<Vec4f> random_vertices(std::mt19937& rng, std::size_t n, float guard, DepthMapping mapping,
                                   bool degenerate) {
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f), w(-0.5f, 3.0f);
  std::vector<Vec4f> out;
  for (std::size_t k = 0; k < n; ++k) {
    const float wk = w(rng);
    const float spread = std::array{1.0f, 1.2f * guard, 3.0f * guard}[k % 3];
    Vec4f v{spread * wk * unit(rng), spread * wk * unit(rng), 1.3f * wk * unit(rng), wk};
    if (k % 17 == 5) v.x = guard * v.w;                                      // on the right plane
    if (k % 19 == 7) v.z = mapping == DepthMapping::Standard ? -v.w : v.w;   // on the near plane
    if (k % 23 == 11) v.z = mapping == DepthMapping::Standard ? v.w : 0.0f;  // on the far plane
    out.push_back(v);
  }
  if (degenerate) {
    out[n / 2] = {0, 0, 0, 0};
    out[n / 3] = {std::numeric_limits<float>::quiet_NaN(), 0, 0, 1};
  }
  return out;
}

std::vector<std::uint32_t> random_corners(std::mt19937& rng, std::size_t vertices, std::size_t triangles) {
  std::uniform_int_distribution<std::uint32_t> index(0, static_cast<std::uint32_t>(vertices - 1));
  std::vector<std::uint32_t> out;
  for (std::size_t t = 0; t < triangles; ++t) {
    const std::uint32_t a = index(rng), b = index(rng);
    out.insert(out.end(), {a, b, t % 29 == 3 ? a : index(rng)});  // some with a repeated vertex
  }
  return out;
}

struct Case {
  std::string name;
  DrawState state;
  RasterSettings raster;
};

std::vector<Case> cases() {
  std::vector<Case> out;
  for (bool mesa : {false, true})
    for (float guard_band : {1.0f, 4.0f}) {
      RasterSettings raster;
      raster.guard_band = guard_band;
      if (mesa) raster = llvmpipe_model(raster);
      const std::string r = std::string(mesa ? "llvmpipe model" : "spec") + ", guard band " +
                            std::to_string(static_cast<int>(guard_band));
      auto add = [&](const std::string& name, auto change) {
        DrawState s;
        change(s);
        out.push_back({r + ", " + name, s, raster});
      };
      add("plain", [](DrawState&) {});
      add("back culled", [](DrawState& s) { s.cull = CullFace::Back; });
      add("front culled, no far plane", [](DrawState& s) {
        s.cull = CullFace::Front;
        s.clip_far = false;
      });
      add("depth clamp", [](DrawState& s) { s.depth_clamp_near = s.depth_clamp_far = true; });
      add("far side clamped", [](DrawState& s) { s.depth_clamp_far = true; });
      add("near side clamped", [](DrawState& s) { s.depth_clamp_near = true; });
      add("on the near plane", [](DrawState& s) { s.vertices_on_near_plane = true; });
      add("far first", [](DrawState& s) { s.far_first = true; });
      add("on the far plane", [](DrawState& s) { s.vertices_on_far_plane = true; });
      add("reversed", [](DrawState& s) { s.depth_mapping = DepthMapping::Reversed; });
    }
  return out;
}

// The setup of a draw, or the error it refused it with.
struct SetUpResult {
  std::optional<SetUpTriangles> triangles;
  std::string error;
};
template <class SetUp>
SetUpResult set_up_or_error(SetUp&& set_up) {
  SetUpResult r;
  try {
    SetUpTriangles t;
    set_up(t);
    r.triangles = std::move(t);
  } catch (const Error& e) {
    r.error = e.what();
  }
  return r;
}

TEST(IndexedDraw, CodedTrivialTestsClipAsTheClipperDoes) {
  std::mt19937 rng(11);
  for (const Case& c : cases()) {
    ClipSettings settings;
    settings.clip_near = !c.state.depth_clamp_near;
    settings.clip_far = c.state.clip_far && !c.state.depth_clamp_far && !c.state.vertices_on_far_plane;
    settings.skip_near_side = c.state.vertices_on_near_plane;
    settings.far_first = c.state.far_first || c.state.vertices_on_far_plane;
    settings.depth_mapping = c.state.depth_mapping;
    settings.mesa = c.raster.mesa_clipper;
    settings.depth_plane_as_clip_distance = one_sided_depth_clamp(c.state);
    settings.guard_band = c.raster.guard_band;
    const TriangleClipper clipper(settings);
    const std::vector<Vec4f> v = random_vertices(rng, 300, c.raster.guard_band, c.state.depth_mapping, true);
    const std::vector<std::uint32_t> corners = random_corners(rng, v.size(), 2000);
    std::size_t clipped = 0, accepted = 0, rejected = 0;
    std::vector<Vec4f> plain, coded;
    for (std::size_t t = 0; t < corners.size(); t += 3) {
      const Vec4f &a = v[corners[t]], &b = v[corners[t + 1]], &d = v[corners[t + 2]];
      clipper.clip(a, b, d, plain);
      clipper.clip(a, b, d, clipper.code(a), clipper.code(b), clipper.code(d), coded);
      ASSERT_TRUE(same_bits(plain, coded)) << c.name << ", triangle " << t / 3;
      const bool whole = plain.size() == 3 && std::memcmp(&plain[0], &a, sizeof(Vec4f)) == 0 &&
                         std::memcmp(&plain[1], &b, sizeof(Vec4f)) == 0 &&
                         std::memcmp(&plain[2], &d, sizeof(Vec4f)) == 0;
      (plain.empty() ? rejected : whole ? accepted : clipped) += 1;
    }
    // Every kind of triangle was met under every state.
    EXPECT_GT(accepted, 20u) << c.name;
    EXPECT_GT(rejected, 20u) << c.name;
    EXPECT_GT(clipped, 20u) << c.name;
  }
}

TEST(IndexedDraw, TheSetUpIsTheGatheredCornersSetUp) {
  std::mt19937 rng(5);
  std::size_t set_up_triangles = 0, refused = 0;
  for (const Case& c : cases())
    for (bool degenerate : {false, true}) {
      const std::string what = c.name + (degenerate ? ", a degenerate vertex" : "");
      const Framebuffer fb(160, 120, DepthFormat::Fixed24);
      const std::vector<Vec4f> v = random_vertices(rng, 300, c.raster.guard_band, c.state.depth_mapping, degenerate);
      const std::vector<std::uint32_t> corners = random_corners(rng, v.size(), 500);
      std::vector<Vec4f> gathered;
      for (std::uint32_t k : corners) gathered.push_back(v[k]);
      const SetUpResult indexed =
          set_up_or_error([&](SetUpTriangles& t) { fb.set_up(v, corners, c.state, c.raster, t); });
      const SetUpResult plain = set_up_or_error([&](SetUpTriangles& t) { fb.set_up(gathered, c.state, c.raster, t); });
      ASSERT_EQ(indexed.error, plain.error) << what;
      if (!plain.triangles) {
        ++refused;
        continue;
      }
      const SetUpTriangles &a = *indexed.triangles, &b = *plain.triangles;
      ASSERT_EQ(a.triangles.size(), b.triangles.size()) << what;
      EXPECT_EQ(0, std::memcmp(a.triangles.data(), b.triangles.data(), a.triangles.size() * sizeof(a.triangles[0])))
          << what;
      EXPECT_EQ(a.counters.triangles, b.counters.triangles) << what;
      EXPECT_EQ(a.counters.clipped, b.counters.clipped) << what;
      EXPECT_EQ(a.counters.culled, b.counters.culled) << what;
      EXPECT_EQ(a.counters.rasterized, b.counters.rasterized) << what;
      set_up_triangles += b.triangles.size();
    }
  EXPECT_GT(set_up_triangles, 10000u);
  EXPECT_GT(refused, 0u);  // the degenerate vertex, refused alike by both
}

// The indexed draw's fragments are the gathered draw's: the same stencil,
// depth and counters on a framebuffer drawn both ways.
TEST(IndexedDraw, TheDrawIsTheGatheredCornersDraw) {
  std::mt19937 rng(9);
  for (const Case& c : cases()) {
    const std::vector<Vec4f> v = random_vertices(rng, 200, c.raster.guard_band, c.state.depth_mapping, false);
    const std::vector<std::uint32_t> corners = random_corners(rng, v.size(), 300);
    std::vector<Vec4f> gathered;
    for (std::uint32_t k : corners) gathered.push_back(v[k]);
    Framebuffer indexed(64, 48, DepthFormat::Fixed24), plain(64, 48, DepthFormat::Fixed24);
    DrawState s = c.state;
    s.depth_write = true;
    s.front.depth_pass = StencilOp::IncrementWrap;
    s.back.depth_fail = StencilOp::DecrementWrap;
    const DrawCounters a = indexed.draw(v, corners, s, c.raster), b = plain.draw(gathered, s, c.raster);
    EXPECT_EQ(a.fragments, b.fragments) << c.name;
    EXPECT_EQ(a.depth_passed, b.depth_passed) << c.name;
    EXPECT_EQ(a.in_view, b.in_view) << c.name;
    EXPECT_EQ(a.rasterized, b.rasterized) << c.name;
    EXPECT_EQ(indexed.stencil(), plain.stencil()) << c.name;
    EXPECT_EQ(indexed.depth(), plain.depth()) << c.name;
    EXPECT_GT(b.fragments, 0u) << c.name;
  }
}

}  // namespace
}  // namespace nearcap::gl
