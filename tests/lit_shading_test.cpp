// The lit frame's shading held against the exact reference's shadow.png:
// on every bundled scene the real GL (llvmpipe) lights the pixels the
// reference lights and leaves dark the ones it leaves dark, and a receiver's
// winding does not matter.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "llvmpipe_fixture.hpp"
#include "nearcap/exact/camera_space.hpp"
#include "nearcap/exact/pixel_reference.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/judge/crack_map.hpp"
#include "nearcap/judge/reference_images.hpp"
#include "nearcap/render/lit_frame.hpp"

namespace nearcap {
namespace {

namespace fs = std::filesystem;
const std::string kScenes = std::string(NEARCAP_SOURCE_DIR) + "/data/scenes";

class LitShadingTest : public test::LlvmpipeTest {};

// `frame` with every visible pixel's stencil made non-zero: each depth draw
// drawn again into the stencil, the depth test failing on the depths it
// wrote itself (the depth functions are strict), every failing fragment
// incrementing.  Its lit frame is the ambient term alone: what each pixel
// looks like in shadow.
gl::ShadowFrame everything_shadowed(const gl::ShadowFrame& frame) {
  gl::ShadowFrame out = frame;
  for (const gl::DrawCall& d : frame.draws) {
    if (d.pass != gl::DrawPass::Depth) continue;
    gl::DrawCall again = d;
    again.pass = gl::DrawPass::Volume;
    again.state.depth_write = false;
    again.state.cull = gl::CullFace::None;
    again.state.front = again.state.back = {gl::StencilOp::IncrementWrap, gl::StencilOp::Keep};
    out.draws.push_back(std::move(again));
  }
  return out;
}

// One pixel (PNG order: top row first) differs between two RGB images.
bool differs(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b, std::size_t png_pixel) {
  return !std::equal(a.begin() + 3 * png_pixel, a.begin() + 3 * png_pixel + 3, b.begin() + 3 * png_pixel);
}

// The reference's Lambert term at pixel (i, j) (GL window coordinates), as
// shadow.png computes it: its face's camera-space normal turned towards the
// eye, the light direction from the visible point.
double reference_lambert(const CameraSpaceScene& cs, const PixelReference& ref, int i, int j) {
  const std::size_t p = ref.index(i, j);
  const auto o = static_cast<std::size_t>(ref.object[p]);
  const auto& t = cs.mesh(o).triangles[ref.face[p]];
  const Vec3d a = cs.vertex_estimate(o, t[0]), b = cs.vertex_estimate(o, t[1]), c = cs.vertex_estimate(o, t[2]);
  Vec3d n = cross(b - a, c - a);
  const Frustum& fr = cs.frustum();
  const Vec3d ray{fr.left + (i + 0.5) / ref.width * (fr.right - fr.left),
                  fr.bottom + (j + 0.5) / ref.height * (fr.top - fr.bottom), -fr.near};
  const Vec3d q = (dot(n, a) / dot(n, ray)) * ray;
  if (dot(n, q) > 0) n = -1.0 * n;
  const BoundedVec3& lb = cs.light(ref.light);
  const Vec3d to_light = Vec3d{lb.x.v, lb.y.v, lb.z.v} - q;
  return dot(n, to_light) / std::sqrt(dot(n, n) * dot(to_light, to_light));
}

// The distance in pixels from pixel (i, j)'s centre to the nearest edge of
// the reference's visible face there, projected to the window from the
// vertex estimates; infinite when a vertex is not in front of the eye.
double distance_to_face_edge(const CameraSpaceScene& cs, const PixelReference& ref, int i, int j) {
  const std::size_t p = ref.index(i, j);
  const auto o = static_cast<std::size_t>(ref.object[p]);
  const auto& t = cs.mesh(o).triangles[ref.face[p]];
  const Frustum& fr = cs.frustum();
  double x[3], y[3];
  for (int k = 0; k < 3; ++k) {
    const Vec3d v = cs.vertex_estimate(o, t[static_cast<std::size_t>(k)]);
    if (!(v.z < 0)) return std::numeric_limits<double>::infinity();
    x[k] = (fr.near * v.x / -v.z - fr.left) / (fr.right - fr.left) * ref.width;
    y[k] = (fr.near * v.y / -v.z - fr.bottom) / (fr.top - fr.bottom) * ref.height;
  }
  const double px = i + 0.5, py = j + 0.5;
  double best = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    const double ax = x[k], ay = y[k], bx = x[(k + 1) % 3], by = y[(k + 1) % 3];
    const double dx = bx - ax, dy = by - ay, len2 = dx * dx + dy * dy;
    const double s = len2 > 0 ? std::clamp(((px - ax) * dx + (py - ay) * dy) / len2, 0.0, 1.0) : 0.0;
    best = std::min(best, std::hypot(px - (ax + s * dx), py - (ay + s * dy)));
  }
  return best;
}

// Below this Lambert term the light may add less than one 8-bit level to a
// pixel in one of the two images, so an image cannot show it: the GL adds
// (1 - ambient 0.2) x albedo x term, the brightest albedo channel at least
// 0.78; shadow.png adds 0.75 x palette colour x term, the brightest channel
// at least 0.80.  The smaller weight, 0.75 x 0.80 = 0.6, sets the level.
constexpr double kUnderOneLevel = 1.0 / (255.0 * 0.6);

// How far a pixel centre may lie from an edge of the reference's face and
// still be given to the neighbouring face by the GL: llvmpipe snaps each
// window-space vertex to 1/256 pixel by rounding (at most sqrt(2)/512 pixel
// from where it was, so a point of the edge moves at most that far), and the
// float32 transforms move the vertices by far less than that at these
// scenes' sizes (about 1e-4 pixel).  The judge compares visible objects only
// (VisibilityMismatch); this is the same outline effect between two faces of
// one object, whose lit states may differ where one faces the light and
// the other does not.
constexpr double kSnapReach = 1.0 / 256.0;

struct ShadingComparison {
  std::size_t lit = 0, dark = 0;  // pixels both call lit, both call dark
  std::size_t visibility = 0, wrong = 0;
  std::size_t grazing = 0, face_edge = 0;  // disagreements explained (kUnderOneLevel, kSnapReach)
  std::size_t disagree = 0;                // disagreements unexplained
  std::string first;                       // the first of those, described
};

// Z-fail (its far plane infinite) on `scene`, light 0, lit by the real GL,
// each pixel called lit or dark from the image itself (the pixel differs
// from the same pixel with every pixel shadowed), and the same for the
// reference's shadow.png (against shadow.png with every seen pixel's exact
// count made non-zero).  Not compared, and counted apart: the pixels the
// judge (crack_map.hpp) does not hold the shading to, with the GL's
// stencil as read back: where the depth pre-pass sees another object than
// the exact centre sample (VisibilityMismatch) and where Z-fail's stencil
// is wrong (WrongLit, WrongShadowed): there the shadow is the method's
// error, not the shading's.  A disagreement is explained, and counted
// apart, where the reference's Lambert term is under kUnderOneLevel or the
// pixel centre is within kSnapReach of its face's edge.
ShadingComparison compare_shading(const Scene& scene) {
  gl::EmulationSettings settings;
  settings.record_draws = true;
  const gl::ShadowFrame frame = gl::render_shadow_frame(scene, 0, gl::ShadowMethod::ZFail, settings);
  render::LitFrameOptions options;
  options.read_stencils = true;
  const render::LitFrame lit = render::render_lit_frame(scene, {frame}, settings.depth, options);
  const render::LitFrame dark = render::render_lit_frame(scene, {everything_shadowed(frame)}, settings.depth);
  const CameraSpaceScene cs(scene);
  const PixelReference ref = compute_pixel_reference(cs, 0);
  PixelReference ref_dark = ref;
  for (std::uint32_t& s : ref_dark.stencil)
    if (s != PixelReference::kNothingSeen) s = std::max<std::uint32_t>(s, 1);
  const std::vector<std::uint8_t> ref_rgb = shadow_rgb(cs, ref), ref_dark_rgb = shadow_rgb(cs, ref_dark);
  gl::ShadowFrame as_drawn = frame;
  as_drawn.draws.clear();
  as_drawn.stencil = lit.stencils.at(0);
  const CrackReport report = judge_frame(as_drawn, ref);

  ShadingComparison out;
  const int w = frame.width, h = frame.height;
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const std::size_t p = frame.index(i, j), png = static_cast<std::size_t>(h - 1 - j) * w + i;
      switch (report.verdict[p]) {
        case PixelVerdict::NothingSeen:
          continue;
        case PixelVerdict::VisibilityMismatch:
          ++out.visibility;
          continue;
        case PixelVerdict::WrongLit:
        case PixelVerdict::WrongShadowed:
          ++out.wrong;
          continue;
        case PixelVerdict::Right:
        case PixelVerdict::CountOnly:
          break;
      }
      const bool gl_lit = differs(lit.rgb, dark.rgb, png), ref_lit = differs(ref_rgb, ref_dark_rgb, png);
      if (gl_lit == ref_lit) {
        ++(gl_lit ? out.lit : out.dark);
        continue;
      }
      const double lambert = reference_lambert(cs, ref, i, j);
      if (std::abs(lambert) < kUnderOneLevel) {
        ++out.grazing;
        continue;
      }
      const double edge = distance_to_face_edge(cs, ref, i, j);
      if (edge < kSnapReach) {
        ++out.face_edge;
        continue;
      }
      if (out.disagree++ == 0) {
        char text[320];
        std::snprintf(text, sizeof text,
                      "pixel (%d, %d) [GL window coordinates]: GL %s (rgb %d %d %d, in shadow %d %d %d, stencil %d), "
                      "reference %s (exact count %u, object %d, face %u, Lambert term %.4g, %.4g pixel from its "
                      "edge)",
                      i, j, gl_lit ? "lit" : "dark", lit.rgb[3 * png], lit.rgb[3 * png + 1], lit.rgb[3 * png + 2],
                      dark.rgb[3 * png], dark.rgb[3 * png + 1], dark.rgb[3 * png + 2], lit.stencils[0][p],
                      ref_lit ? "lit" : "dark", ref.stencil[p], ref.object[p], ref.face[p], lambert, edge);
        out.first = text;
      }
    }
  return out;
}

TEST_F(LitShadingTest, EveryBundledSceneIsLitWhereTheReferenceIsLit) {
  std::vector<fs::path> scenes;
  for (const auto& e : fs::directory_iterator(kScenes))
    if (e.path().extension() == ".json") scenes.push_back(e.path());
  std::sort(scenes.begin(), scenes.end());
  ASSERT_GE(scenes.size(), 10u);
  std::size_t lit = 0, dark = 0;
  for (const fs::path& path : scenes) {
    SCOPED_TRACE(path.filename().string());
    const Scene scene = load_scene(path.string());
    const ShadingComparison c = compare_shading(scene);
    std::printf(
        "[ shading  ] %-32s lit %7zu  dark %7zu  visibility mismatch %3zu  z-fail wrong %3zu  grazing %3zu  face "
        "edge %zu  disagree %zu\n",
        path.filename().string().c_str(), c.lit, c.dark, c.visibility, c.wrong, c.grazing, c.face_edge, c.disagree);
    EXPECT_EQ(c.disagree, 0u) << c.first;
    lit += c.lit;
    dark += c.dark;
    if (path.filename().string().rfind("room", 0) == 0) {
      // The room's walls and floor in light, the torus's shadow on them.
      EXPECT_GT(c.lit, 50000u);
      EXPECT_GT(c.dark, 5000u);
    }
  }
  EXPECT_GT(lit, 1000000u);
  EXPECT_GT(dark, 1000000u);
}

// A floor is a receiver, which need not be closed: one quad, drawn with its
// triangles facing up or facing down, gives the same lit frame, and a lit
// one (the floor's pixels in light are brighter than in shadow).
TEST_F(LitShadingTest, AReceiversWindingDoesNotMatter) {
  const fs::path dir = fs::temp_directory_path() / ("nearcap_lit_shading_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const char* quad = "OFF\n4 2 0\n-4 0 -4\n-4 0 4\n4 0 4\n4 0 -4\n";
  std::ofstream(dir / "up.off") << quad << "3 0 1 2\n3 0 2 3\n";
  std::ofstream(dir / "down.off") << quad << "3 0 2 1\n3 0 3 2\n";
  const std::string torus = fs::absolute(fs::path(NEARCAP_SOURCE_DIR) / "data/meshes/torus.off").string();
  std::vector<render::LitFrame> frames;
  for (const char* floor : {"up.off", "down.off"}) {
    const fs::path scene_path = dir / (std::string(floor) + ".json");
    std::ofstream(scene_path) << R"({"camera": {"eye": [0, 2.5, 5], "target": [0, 0.7, 0], "up": [0, 1, 0],
      "fovy_deg": 50, "near": 0.1, "far": 100, "width": 160, "height": 120},
      "lights": [{"position": [2, 5, 1.5]}],
      "objects": [{"mesh": ")" + torus +
                                     R"(", "translate": [0, 1, 0], "rotate_deg": [60, 0, 20]},
                  {"mesh": ")" + (dir / floor).string() +
                                     R"(", "occluder": false}]})";
    const Scene scene = load_scene(scene_path.string());
    gl::EmulationSettings settings;
    settings.record_draws = true;
    const gl::ShadowFrame frame = gl::render_shadow_frame(scene, 0, gl::ShadowMethod::ZFail, settings);
    frames.push_back(render::render_lit_frame(scene, {frame}, settings.depth));
    if (frames.size() == 1) {
      const render::LitFrame dark = render::render_lit_frame(scene, {everything_shadowed(frame)}, settings.depth);
      // The bottom row sees only the floor, and the light reaches it there.
      const std::size_t bottom = static_cast<std::size_t>(frame.height - 1) * frame.width;
      EXPECT_TRUE(differs(frames[0].rgb, dark.rgb, bottom + frame.width / 2));
    }
  }
  fs::remove_all(dir);
  ASSERT_EQ(frames.size(), 2u);
  std::size_t differ = 0;
  for (std::size_t k = 0; k < frames[0].rgb.size(); ++k) differ += frames[0].rgb[k] != frames[1].rgb[k];
  EXPECT_EQ(differ, 0u);
}

}  // namespace
}  // namespace nearcap
