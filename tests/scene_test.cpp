// Scene files, from inline JSON: both camera forms, every documented key, the
// object transform T * Rz * Ry * Rx * S, and the faults (kind and a message
// fragment naming the element).  The mesh is the unit cube of data/bad/box.off.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include "nearcap/error.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/scene/scene.hpp"

namespace nearcap {
namespace {

using Json = nlohmann::json;

const std::string kDataBad = std::string(NEARCAP_SOURCE_DIR) + "/data/bad";
const std::string kBox = kDataBad + "/box.off";

Json look_at_json() {
  return {{"eye", {0, 1, 8}}, {"target", {0, 0, 0}}, {"up", {0, 1, 0}}, {"fovy_deg", 60},
          {"near", 0.5},      {"far", 100},          {"width", 640},    {"height", 480}};
}
Json exact_camera_json() {
  return {{"view", {{1, 0, 0, 0}, {0, 1, 0, -1}, {0, 0, 1, -8}, {0, 0, 0, 1}}},
          {"frustum", {{"left", -0.75}, {"right", 0.5}, {"bottom", -0.25}, {"top", 0.375}, {"near", 0.5}, {"far", 64}}},
          {"width", 320},
          {"height", 200}};
}
Json minimal_scene() {
  return {{"camera", look_at_json()},
          {"lights", Json::array({{{"position", {2, 5, 1}}}})},
          {"objects", Json::array({{{"mesh", kBox}}})}};
}

Scene parse(const Json& j) { return parse_scene(j.dump(), "inline.json", kDataBad); }

// parse(j) must throw an Error of `kind` whose message holds `fragment`.
void expect_error(const Json& j, ErrorKind kind, const std::string& fragment) {
  try {
    (void)parse(j);
    ADD_FAILURE() << "accepted: " << j.dump() << "\nexpected " << to_string(kind) << " with '" << fragment << "'";
  } catch (const Error& e) {
    EXPECT_EQ(to_string(e.kind()), to_string(kind)) << e.what();
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("inline.json"), std::string::npos) << "names the file: " << e.what();
  }
}

double length(const Vec3d& v) { return std::sqrt(dot(v, v)); }
Vec3d linear(const Affine3d& m, const Vec3d& v) { return m.apply(v) - m.apply({0, 0, 0}); }

// ---- valid scenes -----------------------------------------------------------

TEST(SceneParse, MinimalSceneWithTheConvenientCamera) {
  const Scene s = parse(minimal_scene());
  EXPECT_EQ(s.source, "inline.json");
  EXPECT_EQ(s.camera.width, 640);
  EXPECT_EQ(s.camera.height, 480);
  EXPECT_EQ(s.camera.frustum.near, 0.5);
  EXPECT_EQ(s.camera.frustum.far, 100);
  // top = near tan(fovy / 2), right = top * aspect, symmetric.
  EXPECT_NEAR(s.camera.frustum.top, 0.5 * std::tan(M_PI / 6), 1e-15);
  EXPECT_EQ(s.camera.frustum.bottom, -s.camera.frustum.top);
  EXPECT_DOUBLE_EQ(s.camera.frustum.right, s.camera.frustum.top * 640.0 / 480.0);
  EXPECT_EQ(s.camera.frustum.left, -s.camera.frustum.right);
  ASSERT_EQ(s.lights.size(), 1u);
  EXPECT_EQ(s.lights[0].position.y, 5);
  ASSERT_EQ(s.objects.size(), 1u);
  EXPECT_TRUE(s.objects[0].occluder) << "occluder defaults to true";
  ASSERT_NE(s.objects[0].mesh, nullptr);
  EXPECT_EQ(s.objects[0].mesh->triangle_count(), 12u);
  EXPECT_TRUE(s.objects[0].mesh->has_adjacency()) << "occluders are validated";
  // No transform keys: the identity, exactly.
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 4; ++k) EXPECT_EQ(s.objects[0].object_to_world.rows[i][k], i == k ? 1.0 : 0.0);
}

TEST(SceneParse, UpDefaultsToPlusY) {
  Json with = minimal_scene(), without = minimal_scene();
  without["camera"].erase("up");
  const Scene a = parse(with), b = parse(without);
  EXPECT_EQ(a.camera.view.rows, b.camera.view.rows);
}

TEST(SceneParse, ExactCameraIsStoredAsWritten) {
  Json j = minimal_scene();
  j["camera"] = exact_camera_json();
  const Scene s = parse(j);
  EXPECT_EQ(s.camera.view.rows[1][3], -1.0);
  EXPECT_EQ(s.camera.view.rows[2][3], -8.0);
  EXPECT_EQ(s.camera.view.rows[0][0], 1.0);
  EXPECT_EQ(s.camera.frustum.left, -0.75);
  EXPECT_EQ(s.camera.frustum.right, 0.5);
  EXPECT_EQ(s.camera.frustum.bottom, -0.25);
  EXPECT_EQ(s.camera.frustum.top, 0.375);
  EXPECT_EQ(s.camera.frustum.near, 0.5);
  EXPECT_EQ(s.camera.frustum.far, 64);
  EXPECT_EQ(s.camera.width, 320);
  EXPECT_EQ(s.camera.height, 200);
}

TEST(SceneParse, EveryObjectAndSceneKey) {
  Json j = minimal_scene();
  j["description"] = "all keys";
  j["lights"].push_back({{"position", {-3, 4, 2}}});
  j["objects"] = Json::array({
      {{"mesh", "box.off"}, {"translate", {1, 2, 3}}, {"scale", 2}, {"rotate_deg", {0, 0, 0}}, {"occluder", true}},
      {{"mesh", kBox}, {"matrix", {{0, -1, 0, 4}, {1, 0, 0, 0}, {0, 0, 1, -2}, {0, 0, 0, 1}}}},
      {{"mesh", "open_mesh.off"}, {"scale", 8}, {"translate", {0, -5, 0}}, {"occluder", false}},
  });
  const Scene s = parse(j);
  ASSERT_EQ(s.lights.size(), 2u);
  EXPECT_EQ(s.lights[1].position.x, -3);
  ASSERT_EQ(s.objects.size(), 3u);
  // Relative mesh paths resolve against the base directory.
  EXPECT_NE(s.objects[0].mesh_path.find("data/bad/box.off"), std::string::npos) << s.objects[0].mesh_path;
  // T * S, exactly: x -> 2x + (1, 2, 3).
  const Vec3d p = s.objects[0].object_to_world.apply({0.5, -0.5, 0.25});
  EXPECT_EQ(p.x, 2);
  EXPECT_EQ(p.y, 1);
  EXPECT_EQ(p.z, 3.5);
  // The full matrix is stored as written.
  EXPECT_EQ(s.objects[1].object_to_world.rows[0][1], -1);
  EXPECT_EQ(s.objects[1].object_to_world.rows[0][3], 4);
  EXPECT_EQ(s.objects[1].object_to_world.rows[2][3], -2);
  // A receiver need not be closed; it gets an adjacency with boundary edges.
  EXPECT_FALSE(s.objects[2].occluder);
  ASSERT_TRUE(s.objects[2].mesh->has_adjacency());
  bool boundary = false;
  for (const auto& n : s.objects[2].mesh->neighbours)
    for (FaceIndex g : n) boundary |= g == kNoFace;
  EXPECT_TRUE(boundary);
}

TEST(SceneParse, RotationIsAboutXThenYThenZ) {
  // R = Rz * Ry * Rx.  Rx(90) takes +y to +z, Ry(90) then takes +z to +x; the
  // other order (Rx * Ry) would leave +y at +z.
  Json j = minimal_scene();
  j["objects"][0]["rotate_deg"] = {90, 90, 0};
  j["objects"][0]["translate"] = {0, 0, -20};
  const Scene s = parse(j);
  const Vec3d y = linear(s.objects[0].object_to_world, {0, 1, 0});
  EXPECT_NEAR(y.x, 1, 1e-15);
  EXPECT_NEAR(y.y, 0, 1e-15);
  EXPECT_NEAR(y.z, 0, 1e-15);
  // Rz(90) takes +x to +y.
  j["objects"][0]["rotate_deg"] = {0, 0, 90};
  const Vec3d x = linear(parse(j).objects[0].object_to_world, {1, 0, 0});
  EXPECT_NEAR(x.x, 0, 1e-15);
  EXPECT_NEAR(x.y, 1, 1e-15);
  // Scale applies before rotation and the translation is exact.
  j["objects"][0]["scale"] = -3;
  const Affine3d m = parse(j).objects[0].object_to_world;
  EXPECT_NEAR(linear(m, {1, 0, 0}).y, -3, 1e-14);
  EXPECT_EQ(m.apply({0, 0, 0}).z, -20);
}

TEST(SceneParse, LoadSceneResolvesMeshesAgainstTheSceneFile) {
  // default.json names "../meshes/torus.off": relative to data/scenes/.
  const Scene s = load_scene(std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/default.json");
  ASSERT_EQ(s.objects.size(), 2u);
  EXPECT_NE(s.objects[0].mesh_path.find("data/meshes/torus.off"), std::string::npos) << s.objects[0].mesh_path;
  EXPECT_EQ(s.objects[0].mesh_path.find(".."), std::string::npos) << "lexically normal: " << s.objects[0].mesh_path;
  EXPECT_FALSE(s.objects[1].occluder);
}

// ---- look_at_camera ---------------------------------------------------------

TEST(LookAtCamera, EyeToOriginTargetOntoMinusZ) {
  const Vec3d eye{1, 2, 3}, target{4, -2, 3 + 12}, up{0, 1, 0};
  const Camera c = look_at_camera(eye, target, up, 45, 0.25, 50, 200, 100);
  const Vec3d e = c.view.apply(eye);
  EXPECT_NEAR(e.x, 0, 1e-14);
  EXPECT_NEAR(e.y, 0, 1e-14);
  EXPECT_NEAR(e.z, 0, 1e-14);
  const Vec3d t = c.view.apply(target);
  EXPECT_NEAR(t.x, 0, 1e-13);
  EXPECT_NEAR(t.y, 0, 1e-13);
  EXPECT_NEAR(t.z, -length(target - eye), 1e-13);
  // Rotation: orthonormal rows, determinant +1.
  const Vec3d r0{c.view.rows[0][0], c.view.rows[0][1], c.view.rows[0][2]};
  const Vec3d r1{c.view.rows[1][0], c.view.rows[1][1], c.view.rows[1][2]};
  const Vec3d r2{c.view.rows[2][0], c.view.rows[2][1], c.view.rows[2][2]};
  EXPECT_NEAR(length(r0), 1, 1e-15);
  EXPECT_NEAR(length(r1), 1, 1e-15);
  EXPECT_NEAR(length(r2), 1, 1e-15);
  EXPECT_NEAR(dot(r0, r1), 0, 1e-15);
  EXPECT_NEAR(dot(r1, r2), 0, 1e-15);
  EXPECT_NEAR(dot(cross(r0, r1), r2), 1, 1e-15);
  // Up stays up: camera-space image of +y has no x component and positive y.
  const Vec3d u = linear(c.view, up);
  EXPECT_NEAR(u.x, 0, 1e-15);
  EXPECT_GT(u.y, 0);
  // Frustum.
  EXPECT_NEAR(c.frustum.top, 0.25 * std::tan(M_PI / 8), 1e-16);
  EXPECT_DOUBLE_EQ(c.frustum.right, 2 * c.frustum.top);
  EXPECT_EQ(c.frustum.near, 0.25);
  EXPECT_EQ(c.frustum.far, 50);
  EXPECT_EQ(c.width, 200);
  EXPECT_EQ(c.height, 100);
}

TEST(LookAtCamera, AxisAlignedViewIsExact) {
  // Looking down -z from (0, 0, 5): the basis needs no rounding.
  const Camera c = look_at_camera({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 90, 1, 10, 4, 4);
  const std::array<std::array<double, 4>, 3> expected{{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, -5}}};
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 4; ++k) EXPECT_EQ(c.view.rows[i][k] + 0.0, expected[i][k]) << i << "," << k;
}

// ---- faults -------------------------------------------------------------------

TEST(SceneErrors, UnknownKeysAreNamedAtEveryLevel) {
  Json j = minimal_scene();
  j["lihgts"] = Json::array();
  expect_error(j, ErrorKind::Schema, "lihgts: unknown key");
  j = minimal_scene();
  j["camera"]["fov"] = 60;
  expect_error(j, ErrorKind::Schema, "fov: unknown key");
  j = minimal_scene();
  j["camera"] = exact_camera_json();
  j["camera"]["frustum"]["zfar"] = 1;
  expect_error(j, ErrorKind::Schema, "zfar: unknown key");
  j = minimal_scene();
  j["lights"][0]["colour"] = {1, 1, 1};
  expect_error(j, ErrorKind::Schema, "colour: unknown key");
  j = minimal_scene();
  j["objects"][0]["rotate"] = {0, 0, 0};
  expect_error(j, ErrorKind::Schema, "rotate: unknown key");
}

TEST(SceneErrors, MixedCameraFormsNameTheStrayKey) {
  Json j = minimal_scene();
  j["camera"] = exact_camera_json();
  j["camera"]["eye"] = {0, 0, 1};
  expect_error(j, ErrorKind::Schema, "camera.eye: unknown key");
  j = minimal_scene();
  j["camera"]["view"] = exact_camera_json()["view"];
  expect_error(j, ErrorKind::Schema, "camera.eye: unknown key");  // "view" selects the exact form
}

TEST(SceneErrors, MissingKeysAreNamed) {
  for (const char* key : {"camera", "lights", "objects"}) {
    Json j = minimal_scene();
    j.erase(key);
    expect_error(j, ErrorKind::Schema, key + std::string(": missing required key"));
  }
  for (const char* key : {"eye", "target", "fovy_deg", "near", "far", "width", "height"}) {
    Json j = minimal_scene();
    j["camera"].erase(key);
    expect_error(j, ErrorKind::Schema, key + std::string(": missing required key"));
  }
  Json j = minimal_scene();
  j["camera"] = exact_camera_json();
  j["camera"].erase("frustum");
  expect_error(j, ErrorKind::Schema, "camera.frustum: missing required key");
  j = minimal_scene();
  j["objects"][0].erase("mesh");
  expect_error(j, ErrorKind::Schema, "objects[0].mesh: missing required key");
  j = minimal_scene();
  j["lights"][0].erase("position");
  expect_error(j, ErrorKind::Schema, "lights[0].position: missing required key");
}

TEST(SceneErrors, WrongTypes) {
  auto with = [](const std::function<void(Json&)>& edit) {
    Json j = minimal_scene();
    edit(j);
    return j;
  };
  expect_error(with([](Json& j) { j["camera"]["eye"] = "origin"; }), ErrorKind::Schema, "camera.eye");
  expect_error(with([](Json& j) { j["camera"]["eye"] = {0, 1}; }), ErrorKind::Schema, "expected an array of 3 numbers");
  expect_error(with([](Json& j) { j["camera"]["fovy_deg"] = "60"; }), ErrorKind::Schema, "expected a number");
  expect_error(with([](Json& j) { j["camera"]["width"] = 640.5; }), ErrorKind::Schema, "must be an integer");
  expect_error(with([](Json& j) { j["lights"] = {{"position", {1, 2, 3}}}; }), ErrorKind::Schema, "lights");
  expect_error(with([](Json& j) { j["lights"] = Json::array(); }), ErrorKind::Schema, "non-empty array of lights");
  expect_error(with([](Json& j) { j["objects"] = Json::array(); }), ErrorKind::Schema, "non-empty array of objects");
  expect_error(with([](Json& j) { j["objects"][0]["mesh"] = 7; }), ErrorKind::Schema, "file name string");
  expect_error(with([](Json& j) { j["objects"][0]["occluder"] = "yes"; }), ErrorKind::Schema, "true or false");
  expect_error(with([](Json& j) { j["objects"][0]["scale"] = {2, 2, 2}; }), ErrorKind::Schema, "objects[0].scale");
  expect_error(with([](Json& j) { j["description"] = 3; }), ErrorKind::Schema, "description");
  expect_error(with([](Json& j) { j["lights"][0] = {1, 2, 3}; }), ErrorKind::Schema, "expected a JSON object");
  expect_error(Json::array({1, 2}), ErrorKind::Schema, "expected a JSON object");
}

TEST(SceneErrors, MalformedJsonIsAParseError) {
  try {
    (void)parse_scene("{\"camera\": ", "inline.json", kDataBad);
    ADD_FAILURE() << "accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Parse);
    EXPECT_NE(std::string(e.what()).find("malformed JSON"), std::string::npos) << e.what();
  }
  // A number beyond double's range (the fuzzer's find) is malformed, not a crash.
  try {
    (void)parse_scene("{\"camera\": {\"near\": 1e999}}", "inline.json", kDataBad);
    ADD_FAILURE() << "accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Parse) << e.what();
  }
}

TEST(SceneErrors, MatricesMustBeAffineAndInvertible) {
  Json j = minimal_scene();
  j["camera"] = exact_camera_json();
  j["camera"]["view"][3] = {0, 0, 1, 1};
  expect_error(j, ErrorKind::Schema, "[0, 0, 0, 1]");
  j["camera"]["view"] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  expect_error(j, ErrorKind::Schema, "4 rows");
  j["camera"]["view"] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {2, 0, 0, 0}, {0, 0, 0, 1}};
  expect_error(j, ErrorKind::Camera, "not invertible");
  j = minimal_scene();
  j["objects"][0]["matrix"] = {{1, 1, 0, 0}, {1, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};
  expect_error(j, ErrorKind::Schema, "not invertible");
  j["objects"][0]["matrix"] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};
  j["objects"][0]["translate"] = {1, 0, 0};
  expect_error(j, ErrorKind::Schema, "'matrix' excludes");
  j = minimal_scene();
  j["objects"][0]["scale"] = 0;
  expect_error(j, ErrorKind::Schema, "zero scale");
}

TEST(SceneErrors, CameraFaults) {
  auto with = [](const char* key, const Json& value) {
    Json j = minimal_scene();
    j["camera"][key] = value;
    return j;
  };
  expect_error(with("fovy_deg", 0), ErrorKind::Camera, "fovy_deg");
  expect_error(with("fovy_deg", 180), ErrorKind::Camera, "fovy_deg");
  expect_error(with("near", 0), ErrorKind::Camera, "must be > 0");
  expect_error(with("near", -1), ErrorKind::Camera, "must be > 0");
  expect_error(with("far", 0.5), ErrorKind::Camera, "must be < far");
  expect_error(with("width", 0), ErrorKind::Camera, "outside [1, 16384]");
  expect_error(with("height", 16385), ErrorKind::Camera, "outside [1, 16384]");
  expect_error(with("width", 1e20), ErrorKind::Camera,
               "viewport size 1e+20 is outside [1, 16384]");  // whole, too large
  expect_error(with("width", 64.5), ErrorKind::Schema, "must be an integer number of pixels");
  expect_error(with("target", Json{0, 1, 8}), ErrorKind::Camera, "coincide");
  expect_error(with("up", Json{0, 2, 16}), ErrorKind::Camera, "parallel");  // along target - eye
  expect_error(with("up", Json{0, 0, 0}), ErrorKind::Camera, "parallel");
  Json j = minimal_scene();
  j["camera"] = exact_camera_json();
  j["camera"]["frustum"]["right"] = -0.75;
  expect_error(j, ErrorKind::Camera, "zero-size or inverted");
  j["camera"]["frustum"]["right"] = 0.5;
  j["camera"]["frustum"]["top"] = -1;
  expect_error(j, ErrorKind::Camera, "zero-size or inverted");
}

TEST(SceneErrors, LookAtFrustumThatOverflowsIsRejected) {
  // fovy 120 at near 1e308: top = near tan(60 deg) and right = top * 4/3
  // overflow to infinity.  The frustum check (left < right) passes for
  // -inf < inf, so the scene must be rejected some other way: a camera (or
  // range / non-finite) error, never a scene with an infinite frustum.
  // (Accepted, `nearcap cap` and `nearcap reference` die of SIGFPE on it.)
  Json j = minimal_scene();
  j["camera"]["fovy_deg"] = 120;
  j["camera"]["near"] = 1e308;
  j["camera"]["far"] = 1.5e308;
  j["camera"]["width"] = 64;
  j["camera"]["height"] = 48;
  try {
    const Scene s = parse(j);
    ADD_FAILURE() << "accepted with frustum left " << s.camera.frustum.left << ", right " << s.camera.frustum.right
                  << ", bottom " << s.camera.frustum.bottom << ", top " << s.camera.frustum.top;
  } catch (const Error& e) {
    const ErrorKind k = e.kind();
    EXPECT_TRUE(k == ErrorKind::Camera || k == ErrorKind::Range || k == ErrorKind::NonFinite) << e.what();
  }
}

TEST(SceneErrors, MissingMeshIsAnIoErrorNamingTheObject) {
  Json j = minimal_scene();
  j["objects"].push_back({{"mesh", "no_such_mesh.off"}});
  expect_error(j, ErrorKind::Io, "objects[1]");
  expect_error(j, ErrorKind::Io, "no_such_mesh.off");
}

TEST(SceneErrors, OpenOccluderIsAMeshErrorButAnOpenReceiverIsFine) {
  Json j = minimal_scene();
  j["objects"][0]["mesh"] = "open_mesh.off";
  expect_error(j, ErrorKind::Mesh, "objects[0] (occluder)");
  j["objects"][0]["occluder"] = false;
  j["objects"].push_back({{"mesh", kBox}, {"translate", {0, 0, -3}}});
  EXPECT_NO_THROW((void)parse(j));
}

TEST(SceneErrors, LightsInsideOrOnAnOccluder) {
  Json j = minimal_scene();
  j["lights"][0]["position"] = {0.125, 0.25, -0.125};
  expect_error(j, ErrorKind::Light, "inside");
  j["lights"][0]["position"] = {0.5, 0.25, -0.125};  // on the face x = 1/2
  expect_error(j, ErrorKind::Light, "on the surface");
  j["lights"][0]["position"] = {0.5, 0.5, 0.5};  // a vertex
  expect_error(j, ErrorKind::Light, "on the surface");
  j["lights"][0]["position"] = {0.5 + 0x1p-50, 0.25, -0.125};  // just outside
  EXPECT_NO_THROW((void)parse(j));
  // Only occluders count: inside a receiver is allowed.
  j["lights"][0]["position"] = {0, 0, 0};
  j["objects"][0]["occluder"] = false;
  j["objects"].push_back({{"mesh", kBox}, {"translate", {3, 0, 0}}});
  EXPECT_NO_THROW((void)parse(j));
}

TEST(SceneErrors, CoordinatesBeyondTheFloatPipelineAreARangeError) {
  Json j = minimal_scene();
  j["objects"][0]["translate"] = {0x1p41, 0, 0};
  expect_error(j, ErrorKind::Range, "2^40");
  j = minimal_scene();
  j["lights"][0]["position"] = {0, 0x1p41, 0};
  expect_error(j, ErrorKind::Range, "lights[0]");
}

}  // namespace
}  // namespace nearcap

namespace nearcap {
namespace {

// A sweep's mesh cache: one read for many scenes; a changed file is read
// again; an occluder mesh that fails validation fails every scene naming it.
TEST(MeshCache, ReadsOnceAndAgainWhenTheFileChanges) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("nearcap_mesh_cache_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  fs::copy_file(std::string(NEARCAP_SOURCE_DIR) + "/data/meshes/box.off", dir / "m.off",
                fs::copy_options::overwrite_existing);
  const std::string json = R"({"camera":{"eye":[0,0,5],"target":[0,0,0],"fovy_deg":50,"near":0.5,"far":50,
    "width":8,"height":6},"lights":[{"position":[3,4,5]}],"objects":[{"mesh":"m.off"},{"mesh":"m.off","translate":[3,0,0]}]})";
  MeshCache cache;
  const Scene a = parse_scene(json, "a", dir.string(), &cache);
  const Scene b = parse_scene(json, "b", dir.string(), &cache);
  EXPECT_EQ(cache.reads(), 1u);
  EXPECT_EQ(a.objects[0].mesh.get(), b.objects[1].mesh.get());
  EXPECT_TRUE(a.objects[0].mesh->has_adjacency());
  // Replace the file by a different mesh (an open one: not a valid occluder).
  {
    std::ofstream f(dir / "m.off");
    f << "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  }
  fs::last_write_time(dir / "m.off", fs::last_write_time(dir / "m.off") + std::chrono::seconds(2));
  try {
    parse_scene(json, "c", dir.string(), &cache);
    ADD_FAILURE() << "an open occluder mesh was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Mesh) << e.what();
    EXPECT_NE(std::string(e.what()).find("objects[0]"), std::string::npos) << e.what();
  }
  EXPECT_EQ(cache.reads(), 2u);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace nearcap
