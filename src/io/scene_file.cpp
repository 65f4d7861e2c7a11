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
#include "nearcap/io/json_reader.hpp"
#include "nearcap/io/mesh_file.hpp"
#include "nearcap/numeric/rational.hpp"
#include "nearcap/scene/scene.hpp"
#include "scene_checks.hpp"

namespace nearcap {
namespace {

using Json = nlohmann::json;
using io::JsonValue;

class SceneReader {
 public:
  SceneReader(std::string source, std::string base, MeshCache* cache)
      : source_(std::move(source)), base_(std::move(base)), cache_(cache) {}

  static int pixels(const JsonValue& j) {
    // 64.0 is the integer 64; an integer too large for long long is outside the range too.
    const bool whole = j.is_integer() || (j.is_number() && j.number() == std::floor(j.number()));
    if (!whole)
      j.fail(j.is_number() ? "must be an integer number of pixels"
                           : "expected an integer pixel count, found " + std::string(j.type_name()));
    if (j.number() < 1 || j.number() > 16384) {
      std::ostringstream m;
      m.precision(17);
      m << "viewport size " << j.number() << " is outside [1, 16384] pixels";
      j.fail(ErrorKind::Camera, m.str());
    }
    return static_cast<int>(j.number());
  }

  static Vec3d vec3(const JsonValue& j) {
    const std::vector<JsonValue> e = j.elements(3, "numbers");
    return {e[0].number(), e[1].number(), e[2].number()};
  }

  // Four rows; the last must be [0, 0, 0, 1] (affine); the linear part invertible.
  Affine3d affine(const JsonValue& j, ErrorKind singular_kind) const {
    if (!j.is_array() || j.size() != 4) j.fail("expected 4 rows of 4 numbers, the last [0, 0, 0, 1]");
    Affine3d m;
    const std::vector<JsonValue> rows = j.elements();
    for (int i = 0; i < 4; ++i) {
      const std::vector<JsonValue> row = rows[i].elements(4, "numbers (a row)");
      for (int k = 0; k < 4; ++k) {
        const double v = row[k].number();
        if (i < 3)
          m.rows[i][k] = v;
        else if (v != (k == 3 ? 1.0 : 0.0))
          j.fail("the last row must be exactly [0, 0, 0, 1] (an affine map)");
      }
    }
    if (!scene_checks::invertible(m))
      j.fail(singular_kind, "the matrix is not invertible (its 3x3 linear part has determinant 0)");
    return m;
  }

  Frustum frustum(const JsonValue& j) const {
    j.only_keys({"left", "right", "bottom", "top", "near", "far"});
    Frustum f;
    f.left = j.required<double>("left");
    f.right = j.required<double>("right");
    f.bottom = j.required<double>("bottom");
    f.top = j.required<double>("top");
    f.near = j.required<double>("near");
    f.far = j.required<double>("far");
    check_frustum(f, j.path());
    return f;
  }

  void check_frustum(const Frustum& f, const std::string& where) const {
    scene_checks::check_frustum(f, source_, where);
  }

  Camera camera(const JsonValue& j) const {
    const std::string where = j.path();
    if (j.has("view") || j.has("frustum")) {
      j.only_keys({"view", "frustum", "width", "height"});
      Camera c;
      c.view = affine(j.at("view"), ErrorKind::Camera);
      c.frustum = frustum(j.at("frustum"));
      c.width = pixels(j.at("width"));
      c.height = pixels(j.at("height"));
      return c;
    }
    j.only_keys({"eye", "target", "up", "fovy_deg", "near", "far", "width", "height"});
    const Vec3d eye = vec3(j.at("eye"));
    const Vec3d target = vec3(j.at("target"));
    const Vec3d up = j.has("up") ? vec3(j.at("up")) : Vec3d{0, 1, 0};
    const JsonValue fovy_value = j.at("fovy_deg");
    const double fovy = fovy_value.number();
    if (!(fovy > 0 && fovy < 180)) fovy_value.fail(ErrorKind::Camera, "must lie strictly between 0 and 180 degrees");
    const double near = j.required<double>("near");
    const double far = j.required<double>("far");
    const int width = pixels(j.at("width"));
    const int height = pixels(j.at("height"));
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
    if (f.x == 0 && f.y == 0 && f.z == 0) j.fail(ErrorKind::Camera, "eye and target coincide: no view direction");
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

  // A fault at a path the document does not hold (a derived value).
  [[noreturn]] void fail(ErrorKind kind, const std::string& where, const std::string& what) const {
    throw Error(kind, source_ + ": " + where + ": " + what);
  }

  static Light light(const JsonValue& j) {
    j.only_keys({"position"});
    return Light{vec3(j.at("position"))};
  }

  SceneObject object(const JsonValue& j, std::map<std::string, std::shared_ptr<TriangleMesh>>& meshes,
                     std::set<std::string>& validated) const {
    const std::string where = j.path();
    j.only_keys({"mesh", "translate", "scale", "rotate_deg", "matrix", "occluder"});
    SceneObject o;
    const JsonValue mesh_value = j.at("mesh");
    if (!mesh_value.is_string())
      mesh_value.fail("expected a file name string, found " + std::string(mesh_value.type_name()));
    const std::string mesh = mesh_value.string();
    if (const auto occluder = j.optional<bool>("occluder")) o.occluder = *occluder;
    if (j.has("matrix")) {
      if (j.has("translate") || j.has("scale") || j.has("rotate_deg"))
        j.fail("'matrix' excludes 'translate', 'scale' and 'rotate_deg'");
      o.object_to_world = affine(j.at("matrix"), ErrorKind::Schema);
    } else {
      const Vec3d t = j.has("translate") ? vec3(j.at("translate")) : Vec3d{0, 0, 0};
      double s = 1.0;
      if (const auto scale = j.find("scale")) {
        s = scale->number();
        if (s == 0) scale->fail("a zero scale is not invertible");
      }
      const Vec3d r = j.has("rotate_deg") ? vec3(j.at("rotate_deg")) : Vec3d{0, 0, 0};
      o.object_to_world = trs_matrix(t, r, s);
    }
    std::filesystem::path p(mesh);
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
        what = "mesh '" + mesh + "' (resolved to " + (ec ? o.mesh_path : resolved.lexically_normal().string()) + ")" +
               what.substr(o.mesh_path.size());
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

  Scene scene(const JsonValue& root) const {
    root.only_keys({"camera", "lights", "objects", "description"});
    Scene sc;
    sc.source = source_;
    sc.camera = camera(root.at("camera"));
    const JsonValue lights = root.at("lights");
    if (!lights.is_array() || lights.size() == 0) lights.fail("expected a non-empty array of lights");
    for (const JsonValue& l : lights.elements()) sc.lights.push_back(light(l));
    const JsonValue objects = root.at("objects");
    if (!objects.is_array() || objects.size() == 0) objects.fail("expected a non-empty array of objects");
    std::map<std::string, std::shared_ptr<TriangleMesh>> meshes;
    std::set<std::string> validated;
    for (const JsonValue& o : objects.elements()) sc.objects.push_back(object(o, meshes, validated));
    (void)root.optional<std::string>("description");
    return sc;
  }

 private:
  std::string source_;
  std::string base_;
  MeshCache* cache_;
};

}  // namespace

Scene parse_scene(const std::string& json_text, const std::string& source, const std::string& base_directory,
                  MeshCache* cache) {
  // A number beyond double (5e7154) is malformed JSON, found by fuzz_scene
  // (fuzz/regressions/scene).
  const io::JsonDocument doc = io::JsonDocument::parse(json_text, source);
  Scene sc = SceneReader(source, base_directory, cache).scene(doc.root());
  validate_scene_geometry(sc);
  return sc;
}

std::shared_ptr<const TriangleMesh> MeshCache::get(const std::string& path, bool occluder) {
  struct stat st {};
  const bool stated = ::stat(path.c_str(), &st) == 0;
  const long long size = stated ? static_cast<long long>(st.st_size) : -1;
  const long long mtime = stated ? static_cast<long long>(st.st_mtim.tv_sec) * 1000000000LL + st.st_mtim.tv_nsec : -1;
  std::error_code ec;
  const std::filesystem::path absolute = std::filesystem::absolute(path, ec);
  const std::lock_guard<std::mutex> lock(mutex_);
  Entry& e = entries_[ec ? path : absolute.lexically_normal().string()];
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

void MeshCache::decide_outward_solids() const {
  std::vector<std::shared_ptr<TriangleMesh>> occluders;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& [path, e] : entries_)
      if (e.validated) occluders.push_back(e.mesh);
  }
  for (const auto& mesh : occluders) mesh->bounds_outward_solids();
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
  // A bare file name's folder is the working one (absolute("") is an error).
  std::filesystem::path folder = std::filesystem::path(scene_file).parent_path();
  if (folder.empty()) folder = ".";
  const std::filesystem::path base = std::filesystem::absolute(folder).lexically_normal();
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

Scene load_scene(const std::string& path, MeshCache* cache) {
  const std::string text = io::read_input_file(path, "scene file");
  const std::string base = std::filesystem::path(path).parent_path().string();
  return parse_scene(text, path, base.empty() ? "." : base, cache);
}

}  // namespace nearcap
