// The per-pixel reference: the grids never change an answer, the documented
// tie rules, exact invariances, the image files, the command.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <nlohmann/json.hpp>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "box_scene.hpp"
#include "cli_support.hpp"
#include "nearcap/error.hpp"
#include "nearcap/exact/pixel_reference.hpp"
#include "nearcap/io/image_io.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/judge/reference_images.hpp"
#include "random_scene.hpp"
#include "support/removed_files.hpp"

namespace nearcap {
namespace {

bool same(const PixelSample& a, const PixelSample& b) {
  return a.cap == b.cap && a.stencil == b.stencil && a.object == b.object && a.face == b.face;
}

RC_GTEST_PROP(PixelReference, GridsAgreeWithBruteForce, ()) {
  const auto scene = test::try_parse_scene(test::random_scene_json(*test::random_scene_params()));
  RC_PRE(scene.has_value());
  const CameraSpaceScene cs(*scene);
  const PixelReferenceTracer tracer(cs, 0);
  for (int j = 0; j < scene->camera.height; ++j)
    for (int i = 0; i < scene->camera.width; ++i)
      RC_ASSERT(same(tracer.trace(i, j, nullptr), tracer.trace_brute_force(i, j, nullptr)));
}

// PixelContent::ShadowStatus (first crossing, last shadower first) gives the
// same surface and the same shadow status as the full count.
void expect_same_status(const PixelReference& full, const PixelReference& status) {
  ASSERT_EQ(status.content, PixelContent::ShadowStatus);
  ASSERT_EQ(full.stencil.size(), status.stencil.size());
  EXPECT_EQ(full.object, status.object);
  EXPECT_EQ(full.face, status.face);
  std::size_t differ = 0, shadowed = 0;
  for (std::size_t p = 0; p < full.stencil.size(); ++p) {
    const bool seen = full.stencil[p] != PixelReference::kNothingSeen;
    EXPECT_EQ(seen, status.stencil[p] != PixelReference::kNothingSeen);
    if (!seen) continue;
    shadowed += full.stencil[p] > 0;
    differ += (full.stencil[p] > 0) != (status.stencil[p] == 1) || status.stencil[p] > 1;
  }
  EXPECT_EQ(differ, 0u) << "of " << shadowed << " shadowed pixels";
}

RC_GTEST_PROP(PixelReference, ShadowStatusAgreesWithTheFullCount, ()) {
  const auto scene = test::try_parse_scene(test::random_scene_json(*test::random_scene_params()));
  RC_PRE(scene.has_value());
  const CameraSpaceScene cs(*scene);
  const PixelReferenceTracer tracer(cs, 0);
  const PixelReference full = compute_pixel_reference(tracer);
  const PixelReference status = compute_pixel_reference(tracer, PixelContent::ShadowStatus);
  RC_ASSERT(full.object == status.object);
  RC_ASSERT(status.cap_pixels_by_object.empty());
  for (std::size_t p = 0; p < full.stencil.size(); ++p) {
    if (full.stencil[p] == PixelReference::kNothingSeen) {
      RC_ASSERT(status.stencil[p] == PixelReference::kNothingSeen);
      continue;
    }
    RC_ASSERT(status.stencil[p] == (full.stencil[p] > 0 ? 1u : 0u));
  }
}

TEST(PixelReference, ShadowStatusAgreesWithTheFullCountOnBundledScenes) {
  for (const char* name : {"default.json", "eye_in_shadow.json", "twisted.json", "near_cap_bunny_wall.json"}) {
    SCOPED_TRACE(name);
    const Scene scene = load_scene(std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/" + name);
    const CameraSpaceScene cs(scene);
    const PixelReferenceTracer tracer(cs, 0);
    expect_same_status(compute_pixel_reference(tracer), compute_pixel_reference(tracer, PixelContent::ShadowStatus));
  }
}

RC_GTEST_PROP(PixelReference, InvariantUnderExactTranslation, ()) {
  const test::RandomSceneParams params = *test::random_scene_params();
  const std::array<int, 3> offset = *test::dyadic_offset16(1024);
  const auto a = test::try_parse_scene(test::random_scene_json(params));
  RC_PRE(a.has_value());
  const auto b = test::try_parse_scene(test::random_scene_json(params, offset));
  RC_ASSERT(b.has_value());
  const CameraSpaceScene csa(*a), csb(*b);
  const PixelReference ra = compute_pixel_reference(csa, 0), rb = compute_pixel_reference(csb, 0);
  RC_ASSERT(ra.cap == rb.cap);
  RC_ASSERT(ra.stencil == rb.stencil);
  RC_ASSERT(ra.object == rb.object);
  RC_ASSERT(ra.face == rb.face);
}

// Camera at the origin looking down -z, frustum [-1, 1]^2 at near 1, 2x2
// pixels: pixel centres (+-1/2, +-1/2, -1).  A box [1, 3] x [-1/2, 3/2] x
// [-4, -2]: the ray through pixel (1, 1) meets the box's front-left edge
// (x = 1, z = -2) exactly.  The perturbation nudges the pixel centre away from
// the camera first, which turns the ray slightly towards the axis: it passes
// behind the edge and sees the left face (x = 1).
std::string edge_scene_json(bool occluder) {
  nlohmann::json j;
  j["camera"] = {{"view", {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}}},
                 {"frustum", {{"left", -1}, {"right", 1}, {"bottom", -1}, {"top", 1}, {"near", 1}, {"far", 100}}},
                 {"width", 2},
                 {"height", 2}};
  j["lights"] = nlohmann::json::array({{{"position", {0, 10, 0}}}});
  j["objects"] = nlohmann::json::array(
      {{{"mesh", test::unit_box_path()}, {"translate", {2, 0.5, -3}}, {"scale", 2}, {"occluder", occluder}}});
  return j.dump();
}

TEST(PixelReference, PixelCentreOnAProjectedEdgeFollowsThePerturbation) {
  const Scene scene = parse_scene(edge_scene_json(false), "edge", ".");
  const CameraSpaceScene cs(scene);
  const PixelReferenceTracer tracer(cs, 0);
  const PixelSample s = tracer.trace(1, 1, nullptr);
  ASSERT_TRUE(s.stencil.has_value());
  const auto& t = cs.mesh(0).triangles[s.face];
  // Every vertex of the seen triangle has camera-space x = 1: the left face.
  for (int k = 0; k < 3; ++k) EXPECT_EQ(cs.vertex_estimate(0, t[k]).x, 1.0) << "face " << s.face;
  EXPECT_TRUE(same(s, tracer.trace_brute_force(1, 1, nullptr)));
  // The pixel to its left sees nothing: its ray (x = -t/2) never reaches the box.
  EXPECT_FALSE(tracer.trace(0, 1, nullptr).stencil.has_value());
}

// A view ray exactly on the edge two faces share: the filters cannot decide
// either face's edge form there, and the perturbation gives the ray to
// exactly one of the two, so the surface has no hole on its edges: the one
// the point nudged right (+x, perturbation.hpp) meets.  The
// camera of edge_scene_json; a diamond at z = -5 split along x = 0, which
// holds the view's axis, seen at the window's centre.
TEST(PixelReference, AViewRayOnASharedEdgeSeesOneOfItsFaces) {
  const std::filesystem::path mesh = test::temp_path("nearcap_split_diamond") += ".off";
  std::ofstream(mesh) << "OFF\n4 2 0\n0 -1 -5\n0 1 -5\n-1 0 -5\n1 0 -5\n3 0 1 2\n3 1 0 3\n";
  const test::RemovedFiles removed{mesh};
  nlohmann::json j = nlohmann::json::parse(edge_scene_json(false));
  j["objects"] = nlohmann::json::array({{{"mesh", mesh.string()}, {"occluder", false}}});
  const Scene scene = parse_scene(j.dump(), "split diamond", ".");
  const CameraSpaceScene cs(scene);
  const PixelReferenceTracer tracer(cs, 0);
  FilterStats stats;
  const PixelSample s = tracer.trace_at({1, 1, 0}, &stats);  // the window's centre: the view's axis
  ASSERT_TRUE(s.stencil.has_value()) << "a hole on the shared edge";
  EXPECT_EQ(s.face, 1u) << "the face on the right";
  EXPECT_GE(stats.exact[static_cast<int>(Predicate::RayHit)], 2u) << "both faces' edge forms decided in rationals";
  // Off the edge by a sixteenth of a pixel, the face on that side.
  for (const auto& [x, face] : {std::pair{15, 0u}, std::pair{17, 1u}}) {
    const PixelSample off = tracer.trace_at({x, 16, 4}, nullptr);
    ASSERT_TRUE(off.stencil.has_value()) << x;
    EXPECT_EQ(off.face, face) << x;
  }
}

// The grid around the eye leaves out the faces of an occluder turned away
// from the eye where the occluder lies wholly beyond the near plane (a view
// ray enters it first through a face turned toward the eye): never where a
// face turned away can be the first hit.  Seen along the view's axis (the
// camera of edge_scene_json): the inside of an occluder box the near plane
// cuts (its far face), an open receiver turned away, and the near face of a
// mirrored occluder box beyond the near plane (its faces' winding reversed
// in camera space), and the near face of a component turned inside out.
TEST(PixelReference, AFaceTurnedAwayIsSeenWhereItCanBeTheFirstHit) {
  const std::filesystem::path sheet = test::temp_path("nearcap_turned_away") += ".off";
  std::ofstream(sheet) << "OFF\n3 1 0\n-1 -1 -5\n0 1 -5\n1 -1 -5\n3 0 1 2\n";  // its normal along -z
  // Two boxes in one occluder: the unit box at z = -4 turned inside out, in
  // front of an outward one four times its size at z = -7 (the whole mesh
  // outward, so it is a valid occluder).
  const std::filesystem::path pair = test::temp_path("nearcap_inside_out_box") += ".off";
  {
    std::ofstream out(pair);
    out << "OFF\n16 24 0\n";
    for (const auto& [z, half] : {std::pair{-4.0, 0.5}, std::pair{-7.0, 1.0}})
      for (int k = 0; k < 8; ++k)
        out << ((k & 4) ? half : -half) << " " << ((k & 2) ? half : -half) << " " << z + ((k & 1) ? half : -half)
            << "\n";
    const int faces[12][3] = {{0, 1, 3}, {0, 3, 2}, {4, 6, 7}, {4, 7, 5}, {0, 4, 5}, {0, 5, 1},
                              {2, 3, 7}, {2, 7, 6}, {0, 2, 6}, {0, 6, 4}, {1, 5, 7}, {1, 7, 3}};
    for (const auto& f : faces) out << "3 " << f[0] << " " << f[2] << " " << f[1] << "\n";  // inside out
    for (const auto& f : faces) out << "3 " << f[0] + 8 << " " << f[1] + 8 << " " << f[2] + 8 << "\n";
  }
  const test::RemovedFiles removed{sheet, pair};
  struct Case {
    const char* what;
    nlohmann::json object;
    double seen_z;  // the camera-space z of the face seen
  };
  const Case cases[] = {
      {"a box the near plane cuts",
       {{"mesh", test::unit_box_path()}, {"translate", {0, 0, -1.5}}, {"scale", 2}, {"occluder", true}},
       -2.5},
      {"an open receiver turned away", {{"mesh", sheet.string()}, {"occluder", false}}, -5},
      {"a mirrored box beyond the near plane",
       {{"mesh", test::unit_box_path()}, {"translate", {0, 0, -5}}, {"scale", -2}, {"occluder", true}},
       -4},
      {"a box turned inside out in front of another, one occluder",
       {{"mesh", pair.string()}, {"occluder", true}},
       -3.5},
      {"a box beyond the near plane",
       {{"mesh", test::unit_box_path()}, {"translate", {0, 0, -5}}, {"scale", 2}, {"occluder", true}},
       -4},
  };
  for (const Case& c : cases) {
    nlohmann::json j = nlohmann::json::parse(edge_scene_json(false));
    j["objects"] = nlohmann::json::array({c.object});
    const Scene scene = parse_scene(j.dump(), c.what, ".");
    const CameraSpaceScene cs(scene);
    const PixelReferenceTracer tracer(cs, 0);
    const PixelSample s = tracer.trace_at({1, 1, 0}, nullptr);
    ASSERT_TRUE(s.stencil.has_value()) << c.what << ": nothing seen";
    const auto& t = cs.mesh(0).triangles[s.face];
    for (int k = 0; k < 3; ++k) EXPECT_EQ(cs.vertex_estimate(0, t[k]).z, c.seen_z) << c.what << ", face " << s.face;
  }
}

// Two coplanar faces both hit at a pixel: the lower (object, face) is seen
// (pixel_reference.hpp).  The ground slab twice in one place, seen from
// above: every pixel on its top sees object 0, also without acceleration.
TEST(PixelReference, OfTwoCoplanarFacesTheLowerObjectIsSeen) {
  nlohmann::json j;
  j["camera"] = {{"eye", {0.3, 6, 0.2}}, {"target", {0, 0, 0}}, {"up", {0, 0, -1}},
                 {"fovy_deg", 40},       {"near", 1},           {"far", 50},
                 {"width", 16},          {"height", 12}};
  j["lights"] = nlohmann::json::array({{{"position", {1, 5, 1}}}});
  const std::string ground = std::string(NEARCAP_SOURCE_DIR) + "/data/meshes/ground.off";
  j["objects"] =
      nlohmann::json::array({{{"mesh", ground}, {"occluder", false}}, {{"mesh", ground}, {"occluder", false}}});
  const Scene scene = parse_scene(j.dump(), "twice", ".");
  const CameraSpaceScene cs(scene);
  const PixelReferenceTracer tracer(cs, 0);
  for (int y = 0; y < 12; ++y)
    for (int x = 0; x < 16; ++x) {
      const PixelSample s = tracer.trace(x, y, nullptr);
      ASSERT_TRUE(s.stencil.has_value()) << x << "," << y;
      EXPECT_EQ(s.object, 0) << x << "," << y;
      EXPECT_TRUE(same(s, tracer.trace_brute_force(x, y, nullptr))) << x << "," << y;
    }
}

// A face exactly in the near plane is beyond it, as GL's closed clip volume
// keeps it: the reference sees the face (lit), not the inside of the box.
TEST(PixelReference, AFaceInTheNearPlaneIsSeen) {
  const Scene scene = test::near_plane_face();
  const CameraSpaceScene cs(scene);
  const PixelReferenceTracer tracer(cs, 0);
  for (const auto& [i, j] : {std::pair{0, 0}, std::pair{31, 23}, std::pair{63, 47}, std::pair{5, 40}}) {
    const PixelSample s = tracer.trace(i, j, nullptr);
    ASSERT_TRUE(s.stencil.has_value()) << i << "," << j;
    EXPECT_EQ(s.object, 0);
    EXPECT_EQ(*s.stencil, 0u) << i << "," << j;
    const auto& t = cs.mesh(0).triangles[s.face];
    for (int k = 0; k < 3; ++k) EXPECT_EQ(cs.vertex_estimate(0, t[k]).z, -0.5) << "face " << s.face;
    EXPECT_TRUE(same(s, tracer.trace_brute_force(i, j, nullptr))) << i << "," << j;
  }
  const PixelReference ref = compute_pixel_reference(tracer);
  for (int j = 0; j < ref.height; ++j)
    for (int i = 0; i < ref.width; ++i) {
      ASSERT_TRUE(ref.seen(i, j)) << i << "," << j;
      ASSERT_FALSE(ref.shadowed(i, j)) << i << "," << j;
    }
}

TEST(PixelReference, PgmStoresTheTopRowFirst) {
  const Scene scene = parse_scene(edge_scene_json(false), "edge", ".");
  const CameraSpaceScene cs(scene);
  const PixelReference ref = compute_pixel_reference(cs, 0);
  int w = 0, h = 0;
  const std::vector<std::uint16_t> pgm = decode_pgm16(stencil_pgm(ref), "stencil", &w, &h);
  ASSERT_EQ(w, 2);
  ASSERT_EQ(h, 2);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const std::uint16_t v = pgm[static_cast<std::size_t>(h - 1 - j) * w + i];
      if (ref.seen(i, j))
        EXPECT_EQ(v, ref.stencil[ref.index(i, j)]);
      else
        EXPECT_EQ(v, kPgmNothingSeen);
    }
  // Pixels (1, 1) and (1, 0) see the box, (0, *) see nothing: not symmetric
  // under a vertical flip only if rows are stored in the right order.
  EXPECT_TRUE(ref.seen(1, 1));
  EXPECT_FALSE(ref.seen(0, 0));
}

TEST(PixelReference, DecodeRejectsMalformedPgm) {
  int w = 0, h = 0;
  EXPECT_THROW(decode_pgm16("P2\n1 1\n65535\n0", "x", &w, &h), Error);
  EXPECT_THROW(decode_pgm16("P5\n2 2\n65535\n\x01", "x", &w, &h), Error);
  EXPECT_THROW(decode_pgm16("P5\n1 1\n255\n\x01", "x", &w, &h), Error);
}

TEST(PixelReference, DecodeEndsACommentAtACarriageReturn) {
  // Netpbm: a comment runs to the next line feed or carriage return.
  int w = 0, h = 0;
  const std::string pgm = std::string("P5 # made by hand\r1 1\r65535\n") + '\x01' + '\x02';
  EXPECT_EQ(decode_pgm16(pgm, "x", &w, &h), (std::vector<std::uint16_t>{0x0102}));
  EXPECT_EQ(w, 1);
  EXPECT_EQ(h, 1);
}

// ---- the command ------------------------------------------------------------
int run_cli(const std::string& args, std::string* err) {
  const test::CliResult r = test::run_cli(args, "reference");
  *err = r.err;
  return r.exit_code;
}

std::filesystem::path fresh_directory(const std::string& name) {
  const auto dir = test::temp_path(name);
  std::filesystem::remove_all(dir);
  return dir;
}

// A small valid scene file (the edge scene at 64 x 48 pixels) in the temp directory.
std::string small_scene_file(const std::string& name) {
  nlohmann::json j = nlohmann::json::parse(edge_scene_json(true));
  j["camera"]["width"] = 64;
  j["camera"]["height"] = 48;
  const auto path = test::temp_path("nearcap_reference_test_" + name) += ".json";
  std::ofstream(path) << j.dump();
  return path.string();
}

TEST(ReferenceCommand, WritesTheFourFiles) {
  const auto dir = fresh_directory("nearcap_reference_ok");
  const std::string scene = small_scene_file("ok");
  std::string err;
  ASSERT_EQ(run_cli("reference " + scene + " --light 0 --out " + dir.string(), &err), 0) << err;
  for (const char* f : {"cap.pgm", "stencil.pgm", "shadow.png", "reference.json"})
    EXPECT_TRUE(std::filesystem::exists(dir / f)) << f;
  std::ifstream in(dir / "stencil.pgm", std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  int w = 0, h = 0;
  EXPECT_NO_THROW(decode_pgm16(ss.str(), "stencil.pgm", &w, &h));
  EXPECT_EQ(w, 64);
  EXPECT_EQ(h, 48);
  std::filesystem::remove_all(dir);
  std::filesystem::remove(scene);
}

TEST(ReferenceCommand, BadInputLeavesNoOutput) {
  const std::string scene = small_scene_file("bad");
  std::string err;
  auto dir = fresh_directory("nearcap_reference_bad_light");
  EXPECT_EQ(run_cli("reference " + scene + " --light 7 --out " + dir.string(), &err), 2);
  EXPECT_NE(err.find("--light 7"), std::string::npos) << err;
  EXPECT_FALSE(std::filesystem::exists(dir));
  dir = fresh_directory("nearcap_reference_bad_scene");
  const std::string bad = std::string(NEARCAP_SOURCE_DIR) + "/data/bad/light_inside.json";
  EXPECT_EQ(run_cli("reference " + bad + " --light 0 --out " + dir.string(), &err), 2);
  EXPECT_NE(err.find("error (light)"), std::string::npos) << err;
  EXPECT_FALSE(std::filesystem::exists(dir));
  std::filesystem::remove(scene);
}

}  // namespace
}  // namespace nearcap
