// Scene files: JSON -> Scene, with every fault named by file and JSON path.
#include "nearcap/io/scene_file.hpp"

#include <sys/stat.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <system_error>

#include "nearcap/error.hpp"
#include "nearcap/exact/light_validation.hpp"
#include "nearcap/io/input_files.hpp"
#include "nearcap/io/mesh_file.hpp"
#include "nearcap/numeric/rational.hpp"
#include "nearcap/scene/scene.hpp"
#include "scene_checks.hpp"

namespace nearcap {
namespace {

using Json = nlohmann::json;

class SceneReader {
 public:
  SceneReader(std::string source, std::string base, MeshCache* cache)
      : source_(std::move(source)), base_(std::move(base)), cache_(cache) {}

  [[noreturn]] void fail(ErrorKind kind, const std::string& where, const std::string& what) const {
    throw Error(kind, source_ + ": " + where + ": " + what);
  }

  void only_keys(const Json& obj, const std::string& where, std::initializer_list<const char*> allowed) const {
    if (!obj.is_object())
      fail(ErrorKind::Schema, where, "expected a JSON object, found " + std::string(obj.type_name()));
    std::set<std::string> ok(allowed.begin(), allowed.end());
    std::string unknown;
    for (const auto& [k, v] : obj.items())
      if (!ok.count(k)) unknown += (unknown.empty() ? "'" : ", '") + k + "'";
    if (!unknown.empty()) {
      std::string expected;
      for (const auto* a : allowed) expected += (expected.empty() ? "" : ", ") + std::string(a);
      fail(ErrorKind::Schema, where, "unknown key(s) " + unknown + " (allowed: " + expected + ")");
    }
  }

  const Json& need(const Json& obj, const char* key, const std::string& where) const {
    auto it = obj.find(key);
    if (it == obj.end()) fail(ErrorKind::Schema, where, std::string("missing required key '") + key + "'");
    return *it;
  }

  double number(const Json& j, const std::string& where) const {
    if (!j.is_number()) fail(ErrorKind::Schema, where, "expected a number, found " + std::string(j.type_name()));
    const double v = j.get<double>();
    if (!std::isfinite(v)) fail(ErrorKind::NonFinite, where, "the number is not finite");
    return v;
  }

  int pixels(const Json& j, const std::string& where) const {
    long long v = 0;
    if (j.is_number_integer() || j.is_number_unsigned()) {
      v = j.get<long long>();
    } else if (j.is_number_float() && std::isfinite(j.get<double>()) &&
               j.get<double>() == std::floor(j.get<double>()) && std::fabs(j.get<double>()) <= 1e9) {
      v = static_cast<long long>(j.get<double>());  // 64.0 is the integer 64
    } else {
      fail(ErrorKind::Schema, where,
           j.is_number() ? "must be an integer number of pixels"
                         : "expected an integer pixel count, found " + std::string(j.type_name()));
    }
    if (v < 1 || v > 16384)
      fail(ErrorKind::Camera, where, "viewport size " + std::to_string(v) + " is outside [1, 16384] pixels");
    return static_cast<int>(v);
  }

  Vec3d vec3(const Json& j, const std::string& where) const {
    if (!j.is_array() || j.size() != 3) fail(ErrorKind::Schema, where, "expected an array of 3 numbers");
    return {number(j[0], where + "[0]"), number(j[1], where + "[1]"), number(j[2], where + "[2]")};
  }

  // Four rows; the last must be [0, 0, 0, 1] (affine); the linear part invertible.
  Affine3d affine(const Json& j, const std::string& where, ErrorKind singular_kind) const {
    if (!j.is_array() || j.size() != 4)
      fail(ErrorKind::Schema, where, "expected 4 rows of 4 numbers, the last [0, 0, 0, 1]");
    Affine3d m;
    for (int i = 0; i < 4; ++i) {
      const std::string w = where + "[" + std::to_string(i) + "]";
      if (!j[i].is_array() || j[i].size() != 4) fail(ErrorKind::Schema, w, "expected a row of 4 numbers");
      for (int k = 0; k < 4; ++k) {
        const double v = number(j[i][k], w + "[" + std::to_string(k) + "]");
        if (i < 3)
          m.rows[i][k] = v;
        else if (v != (k == 3 ? 1.0 : 0.0))
          fail(ErrorKind::Schema, where, "the last row must be exactly [0, 0, 0, 1] (an affine map)");
      }
    }
    if (!scene_checks::invertible(m))
      fail(singular_kind, where, "the matrix is not invertible (its 3x3 linear part has determinant 0)");
    return m;
  }

  Frustum frustum(const Json& j, const std::string& where) const {
    only_keys(j, where, {"left", "right", "bottom", "top", "near", "far"});
    Frustum f;
    f.left = number(need(j, "left", where), where + ".left");
    f.right = number(need(j, "right", where), where + ".right");
    f.bottom = number(need(j, "bottom", where), where + ".bottom");
    f.top = number(need(j, "top", where), where + ".top");
    f.near = number(need(j, "near", where), where + ".near");
    f.far = number(need(j, "far", where), where + ".far");
    check_frustum(f, where);
    return f;
  }

  void check_frustum(const Frustum& f, const std::string& where) const {
    scene_checks::check_frustum(f, source_, where);
  }

  Camera camera(const Json& j) const {
    const std::string where = "camera";
    if (!j.is_object()) fail(ErrorKind::Schema, where, "expected a JSON object");
    if (j.contains("view") || j.contains("frustum")) {
      only_keys(j, where, {"view", "frustum", "width", "height"});
      Camera c;
      c.view = affine(need(j, "view", where), where + ".view", ErrorKind::Camera);
      c.frustum = frustum(need(j, "frustum", where), where + ".frustum");
      c.width = pixels(need(j, "width", where), where + ".width");
      c.height = pixels(need(j, "height", where), where + ".height");
      return c;
    }
    only_keys(j, where, {"eye", "target", "up", "fovy_deg", "near", "far", "width", "height"});
    const Vec3d eye = vec3(need(j, "eye", where), where + ".eye");
    const Vec3d target = vec3(need(j, "target", where), where + ".target");
    const Vec3d up = j.contains("up") ? vec3(j["up"], where + ".up") : Vec3d{0, 1, 0};
    const double fovy = number(need(j, "fovy_deg", where), where + ".fovy_deg");
    if (!(fovy > 0 && fovy < 180))
      fail(ErrorKind::Camera, where + ".fovy_deg", "must lie strictly between 0 and 180 degrees");
    const double near = number(need(j, "near", where), where + ".near");
    const double far = number(need(j, "far", where), where + ".far");
    const int width = pixels(need(j, "width", where), where + ".width");
    const int height = pixels(need(j, "height", where), where + ".height");
    Frustum probe;
    probe.near = near;
    probe.far = far;
    probe.left = probe.bottom = -1;
    probe.right = probe.top = 1;
    check_frustum(probe, where);
    for (const auto& [name, v] : {std::pair<const char*, const Vec3d*>{"eye", &eye}, {"target", &target}})
      for (int k = 0; k < 3; ++k)
        if (std::fabs((*v)[k]) > kFloatPipelineCoordinateLimit) {
          std::ostringstream m;
          m.precision(17);
          m << (*v)[k] << " is beyond the float32 pipeline's limit 2^40 (move the scene nearer the origin)";
          fail(ErrorKind::Range, where + "." + name + "[" + std::to_string(k) + "]", m.str());
        }
    const Vec3d f = target - eye;
    if (f.x == 0 && f.y == 0 && f.z == 0) fail(ErrorKind::Camera, where, "eye and target coincide: no view direction");
    if (up.x == 0 && up.y == 0 && up.z == 0)
      fail(ErrorKind::Camera, where + ".up",
           "is the zero vector (up must be non-zero and not parallel to the view direction)");
    Camera c = look_at_camera(eye, target, up, fovy, near, far, width, height);
    // Every derived double is checked before it becomes the exact scene.
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 4; ++k)
        if (!std::isfinite(c.view.rows[r][k]))
          fail(ErrorKind::Camera, where + ".up",
               "is parallel to the view direction (or too small to give one): the view basis is undefined");
    const Frustum& d = c.frustum;
    if (!std::isfinite(d.top) || !std::isfinite(d.right) || !(d.top > 0) || !(d.right > 0)) {
      std::ostringstream m;
      m.precision(17);
      m << "the frustum derived from near = " << near << " and fovy_deg = " << fovy
        << " (top = near tan(fovy/2) = " << d.top << ", right = top width/height = " << d.right
        << ") is degenerate or not finite";
      fail(ErrorKind::Camera, where + ".near", m.str());
    }
    check_frustum(c.frustum, where + " (derived from near, fovy_deg, width and height)");
    return c;
  }

  Light light(const Json& j, const std::string& where) const {
    only_keys(j, where, {"position"});
    return Light{vec3(need(j, "position", where), where + ".position")};
  }

  SceneObject object(const Json& j, const std::string& where,
                     std::map<std::string, std::shared_ptr<TriangleMesh>>& meshes,
                     std::set<std::string>& validated) const {
    only_keys(j, where, {"mesh", "translate", "scale", "rotate_deg", "matrix", "occluder"});
    SceneObject o;
    const Json& mesh = need(j, "mesh", where);
    if (!mesh.is_string()) fail(ErrorKind::Schema, where + ".mesh", "expected a file name string");
    if (j.contains("occluder")) {
      if (!j["occluder"].is_boolean()) fail(ErrorKind::Schema, where + ".occluder", "expected true or false");
      o.occluder = j["occluder"].get<bool>();
    }
    if (j.contains("matrix")) {
      if (j.contains("translate") || j.contains("scale") || j.contains("rotate_deg"))
        fail(ErrorKind::Schema, where, "'matrix' excludes 'translate', 'scale' and 'rotate_deg'");
      o.object_to_world = affine(j["matrix"], where + ".matrix", ErrorKind::Schema);
    } else {
      const Vec3d t = j.contains("translate") ? vec3(j["translate"], where + ".translate") : Vec3d{0, 0, 0};
      const double s = j.contains("scale") ? number(j["scale"], where + ".scale") : 1.0;
      if (s == 0) fail(ErrorKind::Schema, where + ".scale", "a zero scale is not invertible");
      const Vec3d r = j.contains("rotate_deg") ? vec3(j["rotate_deg"], where + ".rotate_deg") : Vec3d{0, 0, 0};
      o.object_to_world = trs_matrix(t, r, s);
    }
    std::filesystem::path p(mesh.get<std::string>());
    if (p.is_relative()) p = std::filesystem::path(base_) / p;
    o.mesh_path = p.lexically_normal().string();
    try {
      if (cache_) {
        o.mesh = cache_->get(o.mesh_path, o.occluder);
        return o;
      }
      auto& slot = meshes[o.mesh_path];
      if (!slot) slot = std::make_shared<TriangleMesh>(read_mesh(o.mesh_path));
      if (o.occluder && !validated.count(o.mesh_path)) {
        validate_occluder(*slot);
        validated.insert(o.mesh_path);
      }
      if (!slot->has_adjacency()) build_adjacency(*slot);
      if (slot->face_planes.plane.size() != slot->triangles.size()) compute_face_planes(*slot);
      o.mesh = slot;
    } catch (const Error& e) {
      // The mesh reader names the mesh file; say which object of which scene.
      // A file that cannot be read is named as the scene wrote it and as it
      // resolved (relative to the scene's directory, made absolute), so that
      // a wrong base directory shows.
      std::string what = e.what();
      if ((e.kind() == ErrorKind::Io || e.kind() == ErrorKind::Resource) && what.rfind(o.mesh_path + ": ", 0) == 0) {
        std::error_code ec;
        const std::filesystem::path resolved = std::filesystem::absolute(o.mesh_path, ec);
        what = "mesh '" + mesh.get<std::string>() + "' (resolved to " +
               (ec ? o.mesh_path : resolved.lexically_normal().string()) + ")" + what.substr(o.mesh_path.size());
      }
      throw Error(e.kind(), source_ + ": " + where + (o.occluder ? " (occluder)" : "") + ": " + what);
    }
    return o;
  }

  // T * Rz * Ry * Rx * S: rotations about X first, then Y, then Z (extrinsic),
  // computed once in double (the exactness convention).  With no rotation the
  // matrix is exact: cos 0 = 1 and sin 0 = 0 exactly.
  static Affine3d trs_matrix(const Vec3d& t, const Vec3d& rotate_deg, double s) {
    auto rot = [](int axis, double deg) {
      Affine3d m;
      if (deg == 0) return m;
      const double rad = deg * (M_PI / 180.0);
      const double c = std::cos(rad), sn = std::sin(rad);
      const int i = (axis + 1) % 3, k = (axis + 2) % 3;
      m.rows[i][i] = c;
      m.rows[i][k] = -sn;
      m.rows[k][i] = sn;
      m.rows[k][k] = c;
      return m;
    };
    Affine3d scale;
    for (int i = 0; i < 3; ++i) scale.rows[i][i] = s;
    Affine3d m = compose_rounded(rot(0, rotate_deg.x), scale);
    m = compose_rounded(rot(1, rotate_deg.y), m);
    m = compose_rounded(rot(2, rotate_deg.z), m);
    for (int i = 0; i < 3; ++i) m.rows[i][3] = t[i];
    return m;
  }

  Scene scene(const Json& root) const {
    only_keys(root, "scene", {"camera", "lights", "objects", "description"});
    Scene sc;
    sc.source = source_;
    sc.camera = camera(need(root, "camera", "scene"));
    const Json& lights = need(root, "lights", "scene");
    if (!lights.is_array() || lights.empty()) fail(ErrorKind::Schema, "lights", "expected a non-empty array of lights");
    for (std::size_t i = 0; i < lights.size(); ++i)
      sc.lights.push_back(light(lights[i], "lights[" + std::to_string(i) + "]"));
    const Json& objects = need(root, "objects", "scene");
    if (!objects.is_array() || objects.empty())
      fail(ErrorKind::Schema, "objects", "expected a non-empty array of objects");
    std::map<std::string, std::shared_ptr<TriangleMesh>> meshes;
    std::set<std::string> validated;
    for (std::size_t i = 0; i < objects.size(); ++i)
      sc.objects.push_back(object(objects[i], "objects[" + std::to_string(i) + "]", meshes, validated));
    if (root.contains("description") && !root["description"].is_string())
      fail(ErrorKind::Schema, "description", "expected a string");
    return sc;
  }

 private:
  std::string source_;
  std::string base_;
  MeshCache* cache_;
};

// nlohmann::json keeps the last of two equal keys; a scene file with one is
// rejected, like an unknown key.  The parser callback sees every key; a stack
// of open containers gives the JSON path for the message.
class DuplicateKeyCheck {
 public:
  explicit DuplicateKeyCheck(std::string source) : source_(std::move(source)), state_(std::make_shared<State>()) {}
  bool operator()(int, Json::parse_event_t event, Json& parsed) const {
    State& st = *state_;
    switch (event) {
      case Json::parse_event_t::object_start:
      case Json::parse_event_t::array_start:
        enter_value(st);
        st.open.push_back({event == Json::parse_event_t::array_start, {}, {}, -1});
        break;
      case Json::parse_event_t::object_end:
      case Json::parse_event_t::array_end:
        st.open.pop_back();
        break;
      case Json::parse_event_t::key: {
        Container& c = st.open.back();
        const std::string key = parsed.get<std::string>();
        if (!c.keys.insert(key).second)
          throw Error(ErrorKind::Schema, source_ + ": " + path(st) + ": duplicate key '" + key +
                                             "' (each key may appear once in an object)");
        c.key = key;
        break;
      }
      case Json::parse_event_t::value:
        enter_value(st);
        break;
    }
    return true;
  }

 private:
  struct Container {
    bool array;
    std::set<std::string> keys;
    std::string key;  // the current member's key (objects)
    long index;       // the current element's index (arrays)
  };
  struct State {
    std::vector<Container> open;
  };
  static void enter_value(State& st) {
    if (!st.open.empty() && st.open.back().array) ++st.open.back().index;
  }
  static std::string path(const State& st) {
    std::string p;
    for (std::size_t k = 0; k + 1 < st.open.size(); ++k) {
      const Container& c = st.open[k];
      if (c.array)
        p += "[" + std::to_string(c.index) + "]";
      else
        p += (p.empty() ? "" : ".") + c.key;
    }
    return p.empty() ? "scene" : p;
  }
  std::string source_;
  std::shared_ptr<State> state_;  // the callback is copied by the parser
};

}  // namespace

Scene parse_scene(const std::string& json_text, const std::string& source, const std::string& base_directory,
                  MeshCache* cache) {
  Json root;
  try {
    root = Json::parse(json_text, DuplicateKeyCheck(source));
  } catch (const nlohmann::json::exception& e) {
    // parse_error, and out_of_range for numbers beyond double (5e7154): both
    // are malformed input.  (Found by fuzz_scene; fuzz/regressions/scene.)
    throw Error(ErrorKind::Parse, source + ": malformed JSON: " + e.what());
  }
  Scene sc;
  try {
    sc = SceneReader(source, base_directory, cache).scene(root);
  } catch (const nlohmann::json::exception& e) {
    throw Error(ErrorKind::Schema, source + ": " + e.what());
  }
  validate_scene_geometry(sc);
  return sc;
}

std::shared_ptr<const TriangleMesh> MeshCache::get(const std::string& path, bool occluder) {
  struct stat st {};
  const bool stated = ::stat(path.c_str(), &st) == 0;
  const long long size = stated ? static_cast<long long>(st.st_size) : -1;
  const long long mtime = stated ? static_cast<long long>(st.st_mtim.tv_sec) * 1000000000LL + st.st_mtim.tv_nsec : -1;
  const std::lock_guard<std::mutex> lock(mutex_);
  Entry& e = entries_[path];
  if (!e.mesh || e.size != size || e.mtime_ns != mtime || !stated) {
    e = Entry{};
    auto mesh = std::make_shared<TriangleMesh>(read_mesh(path));
    ++reads_;
    build_adjacency(*mesh);
    compute_face_planes(*mesh);
    e.mesh = std::move(mesh);
    e.size = size;
    e.mtime_ns = mtime;
  }
  if (occluder && !e.validated) {
    validate_occluder(*e.mesh);
    e.validated = true;
  }
  return e.mesh;
}

std::size_t MeshCache::reads() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return reads_;
}

std::string with_absolute_mesh_paths(const std::string& json_text, const std::string& scene_file) {
  Json root;
  try {
    root = Json::parse(json_text);
  } catch (const Json::exception& e) {
    throw Error(ErrorKind::Parse, scene_file + ": malformed JSON: " + e.what());
  }
  const std::filesystem::path base = std::filesystem::absolute(std::filesystem::path(scene_file).parent_path());
  if (root.is_object() && root.contains("objects") && root["objects"].is_array())
    for (Json& o : root["objects"])
      if (o.is_object() && o.contains("mesh") && o["mesh"].is_string()) {
        const std::filesystem::path mesh(o["mesh"].get<std::string>());
        if (mesh.is_relative()) o["mesh"] = (base / mesh).lexically_normal().string();
      }
  // JSON text is UTF-8 and a file name is bytes: a folder whose name is not
  // UTF-8 cannot be named in a scene file (U+FFFD would name another file).
  try {
    return root.dump();
  } catch (const Json::type_error&) {
    throw Error(ErrorKind::Io, scene_file + ": the folder " + base.string() +
                                   " has a name that is not UTF-8: its meshes' absolute paths cannot be written in "
                                   "a scene file (rename the folder)");
  }
}

Scene load_scene(const std::string& path) {
  const std::string text = io::read_input_file(path, "scene file");
  const std::string base = std::filesystem::path(path).parent_path().string();
  return parse_scene(text, path, base.empty() ? "." : base);
}

}  // namespace nearcap
