// Camera paths (see camera_path.hpp).
#include "nearcap/analysis/camera_path.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>

#include "nearcap/error.hpp"
#include "nearcap/io/input_files.hpp"
#include "nearcap/io/scene_file.hpp"

namespace nearcap::analysis {
namespace {

using Json = nlohmann::json;

[[noreturn]] void fail(const std::string& source, ErrorKind kind, const std::string& where, const std::string& what) {
  throw Error(kind, source + ": " + where + ": " + what);
}

double number(const std::string& source, const Json& j, const std::string& where) {
  if (!j.is_number()) fail(source, ErrorKind::Schema, where, "expected a number, found " + std::string(j.type_name()));
  const double v = j.get<double>();
  if (!std::isfinite(v)) fail(source, ErrorKind::NonFinite, where, "the number is not finite");
  return v;
}

Vec3d vec3(const std::string& source, const Json& j, const std::string& where) {
  if (!j.is_array() || j.size() != 3) fail(source, ErrorKind::Schema, where, "expected an array of 3 numbers");
  return {number(source, j[0], where + "[0]"), number(source, j[1], where + "[1]"),
          number(source, j[2], where + "[2]")};
}

void only_keys(const std::string& source, const Json& j, const std::string& where,
               std::initializer_list<const char*> allowed) {
  if (!j.is_object()) fail(source, ErrorKind::Schema, where, "expected a JSON object");
  for (const auto& [key, value] : j.items()) {
    bool ok = false;
    for (const char* a : allowed) ok = ok || key == a;
    if (!ok) fail(source, ErrorKind::Schema, where, "unknown key '" + key + "'");
  }
}

Vec3d lerp(const Vec3d& a, const Vec3d& b, double t) {
  return {a.x + (b.x - a.x) * t, a.y + (b.y - a.y) * t, a.z + (b.z - a.z) * t};
}

}  // namespace

CameraPath load_camera_path(const std::string& file) {
  CameraPath p;
  p.source = file;
  Json root;
  try {
    root = Json::parse(io::read_input_file(file, "camera path file"));
  } catch (const Json::exception& e) {
    fail(file, ErrorKind::Parse, "path", std::string("malformed JSON: ") + e.what());
  }
  only_keys(file, root, "path", {"description", "scene", "frames", "width", "height", "keyframes"});
  if (root.contains("description")) {
    if (!root["description"].is_string()) fail(file, ErrorKind::Schema, "description", "expected a string");
    p.description = root["description"].get<std::string>();
  }
  if (!root.contains("scene") || !root["scene"].is_string())
    fail(file, ErrorKind::Schema, "scene", "expected the base scene's file name (a string)");
  std::filesystem::path scene(root["scene"].get<std::string>());
  if (scene.is_relative()) scene = std::filesystem::path(file).parent_path() / scene;
  p.scene_file = scene.lexically_normal().string();
  if (!root.contains("frames") || !root["frames"].is_number_integer() || root["frames"].get<long long>() < 1 ||
      root["frames"].get<long long>() > 1000000)
    fail(file, ErrorKind::Schema, "frames", "expected a whole number of frames in [1, 1000000]");
  p.frames = root["frames"].get<int>();

  // The base scene: it must load; its camera gives the defaults.
  Json base;
  try {
    (void)load_scene(p.scene_file);
    base = Json::parse(io::read_input_file(p.scene_file, "scene file"));
  } catch (const Error& e) {
    throw Error(e.kind(), file + ": scene: " + e.what());
  }
  const Json& camera = base.at("camera");
  CameraKeyframe previous;
  const bool look_at = camera.contains("eye");
  if (look_at) {
    previous.up = camera.contains("up") ? vec3(p.scene_file, camera["up"], "camera.up") : Vec3d{0, 1, 0};
    previous.fovy_deg = camera.at("fovy_deg").get<double>();
    previous.near = camera.at("near").get<double>();
    p.far = camera.at("far").get<double>();
  } else {
    p.far = camera.at("frustum").at("far").get<double>();
  }
  p.width = camera.at("width").get<int>();
  p.height = camera.at("height").get<int>();
  for (const auto& [key, value] : {std::pair<const char*, int*>{"width", &p.width}, {"height", &p.height}}) {
    if (!root.contains(key)) continue;
    if (!root[key].is_number_integer() || root[key].get<long long>() < 1 || root[key].get<long long>() > 16384)
      fail(file, ErrorKind::Schema, key, "expected a whole number of pixels in [1, 16384]");
    *value = root[key].get<int>();
  }
  // Mesh paths made absolute, so that a frame's text is a scene file anywhere.
  base = Json::parse(with_absolute_mesh_paths(base.dump(), p.scene_file));
  base.erase("camera");
  base.erase("description");
  p.base_scene_json = base.dump();

  if (!root.contains("keyframes") || !root["keyframes"].is_array() || root["keyframes"].empty())
    fail(file, ErrorKind::Schema, "keyframes", "expected a non-empty array of keyframes");
  for (std::size_t k = 0; k < root["keyframes"].size(); ++k) {
    const Json& j = root["keyframes"][k];
    const std::string where = "keyframes[" + std::to_string(k) + "]";
    only_keys(file, j, where, {"eye", "target", "up", "fovy_deg", "near"});
    if (!j.contains("eye") || !j.contains("target")) fail(file, ErrorKind::Schema, where, "needs 'eye' and 'target'");
    CameraKeyframe kf = previous;
    kf.eye = vec3(file, j["eye"], where + ".eye");
    kf.target = vec3(file, j["target"], where + ".target");
    if (j.contains("up")) kf.up = vec3(file, j["up"], where + ".up");
    if (j.contains("fovy_deg")) kf.fovy_deg = number(file, j["fovy_deg"], where + ".fovy_deg");
    if (j.contains("near")) kf.near = number(file, j["near"], where + ".near");
    if (k == 0 && !look_at && (!j.contains("fovy_deg") || !j.contains("near")))
      fail(file, ErrorKind::Schema, where,
           "the base scene's camera has no fovy_deg and near (view/frustum form): give them here");
    if (!(kf.fovy_deg > 0 && kf.fovy_deg < 180))
      fail(file, ErrorKind::Camera, where + ".fovy_deg", "must lie strictly between 0 and 180 degrees");
    if (!(kf.near > 0 && kf.near < p.far))
      fail(file, ErrorKind::Camera, where + ".near", "must lie strictly between 0 and the scene's far plane");
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
