// Camera paths (see camera_path.hpp).
#include "nearcap/analysis/camera_path.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <utility>

#include "nearcap/error.hpp"
#include "nearcap/io/input_files.hpp"
#include "nearcap/io/json_reader.hpp"
#include "nearcap/io/scene_file.hpp"

namespace nearcap::analysis {
namespace {

using Json = nlohmann::json;

Vec3d vec3(const io::JsonValue& j) {
  const std::vector<io::JsonValue> e = j.elements(3, "numbers");
  return {e[0].number(), e[1].number(), e[2].number()};
}

Vec3d lerp(const Vec3d& a, const Vec3d& b, double t) {
  return {a.x + (b.x - a.x) * t, a.y + (b.y - a.y) * t, a.z + (b.z - a.z) * t};
}

}  // namespace

CameraPath load_camera_path(const std::string& file, MeshCache* meshes) {
  CameraPath p;
  p.source = file;
  const io::JsonDocument doc = io::JsonDocument::parse(io::read_input_file(file, "camera path file"), file);
  const io::JsonValue root = doc.root();
  root.only_keys({"description", "scene", "frames", "width", "height", "keyframes"});
  if (const auto description = root.optional<std::string>("description")) p.description = *description;
  const io::JsonValue scene_value = root.at("scene");
  if (!scene_value.is_string())
    scene_value.fail("expected the base scene's file name (a string), found " + std::string(scene_value.type_name()));
  if (scene_value.string().empty()) scene_value.fail("an empty file name, where the base scene's belongs");
  std::filesystem::path scene(scene_value.string());
  if (scene.is_relative()) scene = std::filesystem::path(file).parent_path() / scene;
  p.scene_file = scene.lexically_normal().string();
  p.frames = static_cast<int>(root.at("frames").integer(1, 1000000, "a whole number of frames"));

  // The base scene: it must load; its camera gives the defaults.
  Json base;
  try {
    (void)load_scene(p.scene_file, meshes);
    base = Json::parse(io::read_input_file(p.scene_file, "scene file"));
  } catch (const Error& e) {
    throw Error(e.kind(), file + ": scene: " + e.what());
  }
  const Json& camera = base.at("camera");
  CameraKeyframe previous;
  const bool look_at = camera.contains("eye");
  if (look_at) {
    if (camera.contains("up"))
      for (int k = 0; k < 3; ++k) previous.up[k] = camera["up"][k].get<double>();
    previous.fovy_deg = camera.at("fovy_deg").get<double>();
    previous.near = camera.at("near").get<double>();
    p.far = camera.at("far").get<double>();
  } else {
    p.far = camera.at("frustum").at("far").get<double>();
  }
  p.width = camera.at("width").get<int>();
  p.height = camera.at("height").get<int>();
  for (const auto& [key, value] : {std::pair<const char*, int*>{"width", &p.width}, {"height", &p.height}})
    if (const auto size = root.find(key))
      *value = static_cast<int>(size->integer(1, 16384, "a whole number of pixels"));
  // Mesh paths made absolute, so that a frame's text is a scene file anywhere.
  base = Json::parse(with_absolute_mesh_paths(base.dump(), p.scene_file));
  base.erase("camera");
  base.erase("description");
  p.base_scene_json = base.dump();

  const io::JsonValue keyframes = root.at("keyframes");
  if (!keyframes.is_array() || keyframes.size() == 0) keyframes.fail("expected a non-empty array of keyframes");
  for (const io::JsonValue& j : keyframes.elements()) {
    const bool first = p.keyframes.empty();
    j.only_keys({"eye", "target", "up", "fovy_deg", "near"});
    CameraKeyframe kf = previous;
    kf.eye = vec3(j.at("eye"));
    kf.target = vec3(j.at("target"));
    if (j.has("up")) kf.up = vec3(j.at("up"));
    if (const auto fovy = j.optional<double>("fovy_deg")) kf.fovy_deg = *fovy;
    if (const auto near = j.optional<double>("near")) kf.near = *near;
    if (first && !look_at && (!j.has("fovy_deg") || !j.has("near")))
      j.fail("the base scene's camera has no fovy_deg and near (view/frustum form): give them here");
    // Inherited values were checked where they were given: a fault is this keyframe's.
    if (!(kf.fovy_deg > 0 && kf.fovy_deg < 180))
      throw Error(ErrorKind::Camera, file + ": " + j.path() + ".fovy_deg: must lie strictly between 0 and 180 degrees");
    if (!(kf.near > 0 && kf.near < p.far))
      throw Error(ErrorKind::Camera,
                  file + ": " + j.path() + ".near: must lie strictly between 0 and the scene's far plane");
    p.keyframes.push_back(kf);
    previous = kf;
  }
  return p;
}

CameraKeyframe path_camera(const CameraPath& path, int frame) {
  if (frame < 0 || frame >= path.frames)
    throw Error(ErrorKind::Usage, path.source + ": frame " + std::to_string(frame) + " is not in [0, " +
                                      std::to_string(path.frames) + ")");
  const std::size_t n = path.keyframes.size();
  if (n == 1 || path.frames == 1) return path.keyframes.front();
  const double s = static_cast<double>(frame) / (path.frames - 1) * static_cast<double>(n - 1);
  const std::size_t k = std::min(static_cast<std::size_t>(s), n - 2);
  const double t = s - static_cast<double>(k);
  const CameraKeyframe &a = path.keyframes[k], &b = path.keyframes[k + 1];
  if (t == 0) return a;
  if (t == 1) return b;
  CameraKeyframe c;
  c.eye = lerp(a.eye, b.eye, t);
  c.target = lerp(a.target, b.target, t);
  c.up = lerp(a.up, b.up, t);
  c.fovy_deg = a.fovy_deg + (b.fovy_deg - a.fovy_deg) * t;
  c.near = a.near * std::pow(b.near / a.near, t);
  // Keyframes far apart in double (eyes at +-1e308, near planes 5e-324 and
  // 50) can interpolate past its range.
  const std::pair<const char*, bool> finite[] = {
      {"eye", std::isfinite(c.eye.x) && std::isfinite(c.eye.y) && std::isfinite(c.eye.z)},
      {"target", std::isfinite(c.target.x) && std::isfinite(c.target.y) && std::isfinite(c.target.z)},
      {"up", std::isfinite(c.up.x) && std::isfinite(c.up.y) && std::isfinite(c.up.z)},
      {"fovy_deg", std::isfinite(c.fovy_deg)},
      {"near", std::isfinite(c.near)}};
  for (const auto& [field, ok] : finite)
    if (!ok)
      throw Error(ErrorKind::Range, path.source + ": frame " + std::to_string(frame) + ": keyframes " +
                                        std::to_string(k) + " and " + std::to_string(k + 1) +
                                        " interpolate past double's range in " + field +
                                        " (their values are too far apart)");
  return c;
}

std::string path_frame_json(const CameraPath& path, int frame) {
  const CameraKeyframe c = path_camera(path, frame);
  Json j = Json::parse(path.base_scene_json);
  j["description"] = path.source + ", frame " + std::to_string(frame) + " of " + std::to_string(path.frames);
  j["camera"] = {{"eye", {c.eye.x, c.eye.y, c.eye.z}},
                 {"target", {c.target.x, c.target.y, c.target.z}},
                 {"up", {c.up.x, c.up.y, c.up.z}},
                 {"fovy_deg", c.fovy_deg},
                 {"near", c.near},
                 {"far", path.far},
                 {"width", path.width},
                 {"height", path.height}};
  // The description names the path file: a name that is not UTF-8 gets U+FFFD
  // (the mesh paths are UTF-8: with_absolute_mesh_paths refuses the others).
  return j.dump(-1, ' ', false, Json::error_handler_t::replace);
}

}  // namespace nearcap::analysis
