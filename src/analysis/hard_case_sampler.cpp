// Hard configurations (see hard_case_sampler.hpp).
#include "nearcap/analysis/hard_case_sampler.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <filesystem>
#include <random>
#include <sstream>

#include "nearcap/error.hpp"

namespace nearcap::analysis {
namespace {

using Json = nlohmann::json;
using V3 = std::array<double, 3>;

// The bundled meshes the configurations are built of (data/meshes): a box
// (occluders and the floor), a torus, the real meshes, and the bunny where
// the spec allows it.
constexpr const char* kBoxMesh = "box.off";
constexpr const char* kTorusMesh = "torus.off";
constexpr const char* kRealMeshes[] = {"eight.off", "knot1.off"};
constexpr const char* kBunnyMesh = "bunny.off";

// SplitMix64: decorrelates (seed, index) into one generator seed.
std::uint64_t splitmix(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

struct Occluder {
  std::string mesh;  // file name in the mesh directory
  V3 centre{};
  double scale = 1;
  V3 rotation_deg{};
};

class Builder {
 public:
  Builder(const SamplerSpec& spec, std::uint64_t index) : spec_(spec), rng_(splitmix(spec.seed ^ splitmix(index))) {}

  int uniform(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng_); }
  double sixteenths(int lo, int hi) { return uniform(lo, hi) / 16.0; }

  HardCase build(std::uint64_t index) {
    HardCase out;
    out.seed = spec_.seed;
    out.index = index;
    out.kind = spec_.kinds.at(static_cast<std::size_t>(uniform(0, static_cast<int>(spec_.kinds.size()) - 1)));
    // The common configuration: a camera looking down -z, one light above,
    // one rotated box between them, a receiver slab below.
    eye_ = {sixteenths(-8, 8), sixteenths(-8, 8), sixteenths(8, 24)};
    near_ = uniform(4, 32) / 64.0;
    half_width_ = uniform(8, 40) / 64.0;
    lights_ = {{sixteenths(-40, 40), sixteenths(24, 96), sixteenths(-64, 16)}};
    // One draw a statement where the order matters: the order in which a
    // call's arguments or an operator's operands are evaluated is the
    // compiler's choice, and a seed names the same configurations under every
    // compiler.
    const double box_scale = sixteenths(4, 20);
    const V3 box_centre{sixteenths(-20, 20), sixteenths(-4, 28), sixteenths(-56, 4)};
    occluders_ = {box(box_centre, box_scale)};
    std::ostringstream detail;
    switch (out.kind) {
      case HardCaseKind::LightNearNearPlane: {
        const int k = uniform(1, 40);
        const bool below = uniform(0, 1) == 1;
        lights_[0][2] = eye_[2] - near_ + (below ? -1 : 1) * std::ldexp(1.0, -k);
        occluders_[0].centre = {eye_[0] + sixteenths(-4, 4), eye_[1] + sixteenths(-4, 4) + 0.25, eye_[2] - near_ - 0.5};
        detail << "light 2^-" << k << (below ? " beyond" : " before") << " the near plane";
        break;
      }
      case HardCaseKind::LightInNearPlane:
        lights_[0][2] = eye_[2] - near_;
        occluders_[0].centre = {eye_[0] + sixteenths(-4, 4), eye_[1] + sixteenths(-4, 4) + 0.25, eye_[2] - near_ - 0.5};
        detail << "light exactly in the near plane";
        break;
      case HardCaseKind::Grazing: {
        occluders_[0].rotation_deg = {0, 0, 0};
        const int face = uniform(0, 2);  // level with the top, a side, or the front face
        const int axis = face == 0 ? 1 : face == 1 ? 0 : 2;
        lights_[0][axis] = occluders_[0].centre[axis] + occluders_[0].scale / 2;
        detail << "light level with the box's " << (face == 0 ? "top" : face == 1 ? "side" : "front") << " face";
        break;
      }
      case HardCaseKind::EyeInShadow: {
        const int f = uniform(4, 12);
        for (int k = 0; k < 3; ++k) occluders_[0].centre[k] = eye_[k] + (lights_[0][k] - eye_[k]) * f / 16.0;
        detail << "occluder " << f << "/16 of the way from the eye to the light";
        break;
      }
      case HardCaseKind::FarFromOrigin: {
        const bool binary = uniform(0, 1) == 1;
        const int magnitude = uniform(1, 3);
        const int m = magnitude * (uniform(0, 1) ? 1 : -1);
        offset_ = {binary ? std::ldexp(m, 20) : m * 1e6, 0, 0};
        const int axis = uniform(0, 2);
        std::swap(offset_[0], offset_[axis]);
        detail << "offset " << (binary ? std::to_string(m) + "*2^20" : std::to_string(m) + "e6") << " along "
               << "xyz"[axis];
        break;
      }
      case HardCaseKind::TinyNear: {
        const bool decimal = uniform(0, 3) == 0;
        const int k = uniform(10, 20);
        near_ = decimal ? 1e-6 : std::ldexp(1.0, -k);
        half_width_ = near_ * uniform(16, 64) / 32.0;
        detail << "near " << (decimal ? std::string("1e-6") : "2^-" + std::to_string(k));
        break;
      }
      case HardCaseKind::Straddling: {
        occluders_[0].scale = near_ * uniform(8, 15) / 16.0;
        occluders_[0].centre = {eye_[0] + occluders_[0].scale * uniform(-4, 4) / 8.0,
                                eye_[1] + occluders_[0].scale * uniform(-4, 4) / 8.0, eye_[2] - near_};
        detail << "box of size " << occluders_[0].scale << " centred on the near plane";
        break;
      }
      case HardCaseKind::SeveralOccluders: {
        const int n = uniform(2, 4);
        for (int k = 1; k < n; ++k) {
          const V3 c{sixteenths(-20, 20), sixteenths(-4, 28), sixteenths(-56, 4)};
          occluders_.push_back(uniform(0, 1) ? box(c, sixteenths(4, 16)) : torus(c, sixteenths(4, 12)));
        }
        detail << n << " occluders";
        break;
      }
      case HardCaseKind::SeveralLights: {
        const int n = uniform(2, 3);
        for (int k = 1; k < n; ++k) lights_.push_back({sixteenths(-40, 40), sixteenths(24, 96), sixteenths(-64, 16)});
        detail << n << " lights";
        break;
      }
      case HardCaseKind::RealMesh: {
        std::vector<std::string> meshes(std::begin(kRealMeshes), std::end(kRealMeshes));
        if (spec_.allow_bunny) meshes.push_back(kBunnyMesh);
        occluders_[0].mesh = meshes[static_cast<std::size_t>(uniform(0, static_cast<int>(meshes.size()) - 1))];
        occluders_[0].scale = sixteenths(8, 24);
        detail << occluders_[0].mesh;
        break;
      }
      case HardCaseKind::EyeNearVolume:
        eye_near_volume(detail);
        break;
      case HardCaseKind::FarLight:
        far_light(detail);
        break;
    }
    out.detail = detail.str();
    out.scene_json = scene_json(out);
    return out;
  }

 private:
  // HardCaseKind::EyeNearVolume: an axis-aligned box, and the eye placed
  // where AtomicZP's eye count is decided by a hair.
  void eye_near_volume(std::ostringstream& detail) {
    Occluder& b = occluders_[0];
    b.rotation_deg = {0, 0, 0};
    const V3 l = lights_[0];
    const int variant = uniform(0, 3);
    const int m = uniform(-8, 8);
    const int e = uniform(18, 40);
    const double offset = std::ldexp(m, -e);
    const int axis = uniform(0, 2);
    if (variant <= 1) {
      // A corner of the box (variant 0), or the midpoint of an edge (1);
      // the eye beyond it from the light, on the ray from the light, then
      // moved by `offset` along one axis.
      V3 v{};
      for (int k = 0; k < 3; ++k) v[k] = b.centre[k] + (uniform(0, 1) ? 0.5 : -0.5) * b.scale;
      if (variant == 1) {
        const int a = uniform(0, 2);
        v[a] = b.centre[a];
      }
      const double t = uniform(1, 8) / 16.0;
      for (int k = 0; k < 3; ++k) eye_[k] = v[k] + t * (v[k] - l[k]);
      eye_[axis] += offset;
      detail << "eye " << t << " beyond a box " << (variant == 0 ? "corner" : "edge's midpoint")
             << " from the light, moved " << m << "*2^-" << e << " along "
             << "xyz"[axis];
    } else if (variant == 2) {
      // Near the light: a short segment, all its tests tiny numbers.
      eye_ = l;
      eye_[axis] += offset != 0 ? offset : std::ldexp(1.0, -e);
      detail << "eye " << (offset != 0 ? m : 1) << "*2^-" << e << " from the light along "
             << "xyz"[axis];
    } else {
      // The box behind the camera (which looks down -z), on the segment from
      // the eye to a light behind it: the eye in a volume whose occluder it
      // cannot see.
      lights_[0][2] = eye_[2] + sixteenths(16, 64);
      const int f = uniform(4, 12);
      for (int k = 0; k < 3; ++k) b.centre[k] = eye_[k] + (lights_[0][k] - eye_[k]) * f / 16.0;
      b.scale = sixteenths(4, 8);
      detail << "box behind the eye, " << f << "/16 of the way to the light";
    }
  }

  // HardCaseKind::FarLight: the light 10^k (k = 2 .. 8) or 2^k (k = 7 .. 27)
  // units along a direction d above the scene, from the common box, or
  // (from_eye) from a box placed 1 to 3 units from the eye towards the
  // light, the eye then moved along x by up to half the box's size (in its
  // shadow, or at the edge).
  void far_light(std::ostringstream& detail) {
    const V3 d{sixteenths(-16, 16), sixteenths(8, 32), sixteenths(-16, 8)};
    const double length = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    const bool decimal = uniform(0, 1) == 1;
    const int k = decimal ? uniform(2, 8) : uniform(7, 27);
    const double distance = decimal ? std::pow(10.0, k) : std::ldexp(1.0, k);
    const bool from_eye = uniform(0, 1) == 1;
    if (from_eye) {
      const double t = sixteenths(16, 48);
      V3 centre;
      for (int a = 0; a < 3; ++a) centre[a] = eye_[a] + d[a] / length * t;
      occluders_[0] = box(centre, sixteenths(4, 12));
      eye_[0] += occluders_[0].scale * uniform(-8, 8) / 16.0;
      detail << "box " << t << " from the eye towards the light, ";
    }
    for (int a = 0; a < 3; ++a) lights_[0][a] = occluders_[0].centre[a] + d[a] / length * distance;
    detail << "light " << (decimal ? "1e" : "2^") << k << " away along (" << d[0] << ", " << d[1] << ", " << d[2]
           << ")";
  }

  Occluder box(const V3& centre, double scale) {
    return {kBoxMesh, centre, scale, {double(uniform(0, 89)), double(uniform(0, 89)), double(uniform(0, 89))}};
  }
  Occluder torus(const V3& centre, double scale) {
    return {kTorusMesh, centre, scale, {double(uniform(0, 89)), double(uniform(0, 89)), double(uniform(0, 89))}};
  }
  V3 shifted(V3 v) const {
    for (int k = 0; k < 3; ++k) v[k] += offset_[k];
    return v;
  }
  std::string mesh_path(const std::string& name) const {
    return (std::filesystem::absolute(spec_.mesh_directory) / name).lexically_normal().string();
  }

  std::string scene_json(const HardCase& c) const {
    const V3 e = shifted(eye_);
    const double half_height = half_width_ * spec_.height / spec_.width;
    Json j;
    j["description"] = "hard case " + std::to_string(c.index) + " of seed " + std::to_string(c.seed) + ": " +
                       std::string(to_string(c.kind)) + ", " + c.detail;
    j["camera"] = {{"view", {{1, 0, 0, -e[0]}, {0, 1, 0, -e[1]}, {0, 0, 1, -e[2]}, {0, 0, 0, 1}}},
                   {"frustum",
                    {{"left", -half_width_},
                     {"right", half_width_},
                     {"bottom", -half_height},
                     {"top", half_height},
                     {"near", near_},
                     {"far", 64}}},
                   {"width", spec_.width},
                   {"height", spec_.height}};
    j["lights"] = Json::array();
    for (const V3& l : lights_) j["lights"].push_back({{"position", shifted(l)}});
    j["objects"] = Json::array();
    for (const Occluder& o : occluders_) {
      Json jo = {{"mesh", mesh_path(o.mesh)}, {"translate", shifted(o.centre)}, {"scale", o.scale}};
      if (o.rotation_deg != V3{0, 0, 0}) jo["rotate_deg"] = o.rotation_deg;
      j["objects"].push_back(jo);
    }
    j["objects"].push_back(
        {{"mesh", mesh_path(kBoxMesh)}, {"translate", shifted({0, -9.5, 0})}, {"scale", 16}, {"occluder", false}});
    // JSON text is UTF-8 and a file name is bytes (U+FFFD would name another file).
    try {
      return j.dump();
    } catch (const Json::type_error&) {
      throw Error(ErrorKind::Io, spec_.mesh_directory +
                                     ": the mesh folder's path is not UTF-8, which a scene file cannot name (set "
                                     "NEARCAP_DATA_DIR to a folder whose path is)");
    }
  }

  const SamplerSpec& spec_;
  std::mt19937_64 rng_;
  V3 eye_{}, offset_{0, 0, 0};
  double near_ = 0.25, half_width_ = 0.25;
  std::vector<V3> lights_;
  std::vector<Occluder> occluders_;
};

}  // namespace

std::string_view to_string(HardCaseKind kind) { return name_of(kind); }

std::vector<HardCaseKind> all_hard_case_kinds() {
  std::vector<HardCaseKind> kinds;
  for (int k = 0; k < kHardCaseKindCount; ++k)
    if (!asked_for_by_name_only(static_cast<HardCaseKind>(k))) kinds.push_back(static_cast<HardCaseKind>(k));
  return kinds;
}

bool asked_for_by_name_only(HardCaseKind kind) {
  return kind == HardCaseKind::EyeNearVolume || kind == HardCaseKind::FarLight;
}

HardCaseKind hard_case_kind_from_string(std::string_view name) {
  if (const std::optional<HardCaseKind> kind = value_named<HardCaseKind>(name)) return *kind;
  throw Error(ErrorKind::Usage,
              "unknown hard-case kind '" + std::string(name) + "' (one of " + names_joined<HardCaseKind>() + ")");
}

std::vector<std::string> sampler_mesh_files(const SamplerSpec& spec) {
  std::vector<std::string> names{kBoxMesh, kTorusMesh};
  names.insert(names.end(), std::begin(kRealMeshes), std::end(kRealMeshes));
  if (spec.allow_bunny) names.push_back(kBunnyMesh);
  std::vector<std::string> files;
  for (const std::string& name : names)
    files.push_back((std::filesystem::absolute(spec.mesh_directory) / name).lexically_normal().string());
  return files;
}

HardCaseSampler::HardCaseSampler(SamplerSpec spec) : spec_(std::move(spec)) {
  if (spec_.kinds.empty()) throw Error(ErrorKind::Usage, "the sampler needs at least one kind");
  if (spec_.width < 1 || spec_.height < 1 || spec_.width > 16384 || spec_.height > 16384)
    throw Error(ErrorKind::Usage, "the sampler's width and height must be in [1, 16384]");
  if (spec_.mesh_directory.empty()) throw Error(ErrorKind::Usage, "the sampler needs the mesh directory (data/meshes)");
}

HardCase HardCaseSampler::sample(std::uint64_t index) const { return Builder(spec_, index).build(index); }

}  // namespace nearcap::analysis
