// The runtime switch policy (see switch_policy.hpp).
#include "nearcap/analysis/switch_policy.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <set>

#include "nearcap/analysis/work_estimate.hpp"
#include "nearcap/error.hpp"
#include "nearcap/exact/light_pyramid.hpp"
#include "nearcap/gl/light_frustum.hpp"
#include "nearcap/io/input_files.hpp"

namespace nearcap::analysis {
namespace {

using Json = nlohmann::json;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double log10_or_nan(double v) { return std::isfinite(v) ? std::log10(std::max(std::fabs(v), 1e-15)) : kNaN; }

// A well-formed JSON file that is not a policy: a Schema error naming the field.
[[noreturn]] void fail(const std::string& source, const std::string& field, const std::string& what) {
  throw Error(ErrorKind::Schema, source + ": " + field + ": " + what);
}

// The parser callback: nlohmann::json keeps the last of two equal keys, so a
// policy with one would be read silently with half of it ignored; here it is
// a Schema error naming the key's path.  It also tracks the path of the value
// being parsed, so that a parse error (1e999 overflows a double) can name the
// field it is in.
class KeyTracker {
 public:
  explicit KeyTracker(std::string source) : source_(std::move(source)), state_(std::make_shared<State>()) {}

  bool operator()(int, Json::parse_event_t event, Json& parsed) const {
    State& st = *state_;
    switch (event) {
      case Json::parse_event_t::object_start:
      case Json::parse_event_t::array_start:
        next_element(st);
        st.open.push_back({event == Json::parse_event_t::array_start, {}, "", -1});
        break;
      case Json::parse_event_t::object_end:
      case Json::parse_event_t::array_end:
        st.open.pop_back();
        break;
      case Json::parse_event_t::key: {
        Open& o = st.open.back();
        o.key = parsed.get<std::string>();
        if (!o.keys.insert(o.key).second) fail(source_, path(), "duplicate key (each key appears once in an object)");
        break;
      }
      case Json::parse_event_t::value:
        next_element(st);
        break;
    }
    return true;
  }

  // Where the parser is: "crack_model.bias", "crack_model.mean[2]", or
  // "(top level)".
  std::string path() const {
    std::string p;
    const std::vector<Open>& open = state_->open;
    for (std::size_t k = 0; k < open.size(); ++k) {
      const Open& o = open[k];
      // The innermost array's next element is the one being parsed; an outer
      // array's current one holds the containers opened inside it.
      if (o.array)
        p += "[" + std::to_string(k + 1 == open.size() ? o.index + 1 : o.index) + "]";
      else if (!o.key.empty())
        p += (p.empty() ? "" : ".") + o.key;
    }
    return p.empty() ? "(top level)" : p;
  }

 private:
  struct Open {
    bool array;
    std::set<std::string> keys;
    std::string key;  // objects: the current member's
    long index;       // arrays: the current element's
  };
  struct State {
    std::vector<Open> open;
  };
  // A value, object or array starts: in an array it is the next element.
  static void next_element(State& st) {
    if (!st.open.empty() && st.open.back().array) ++st.open.back().index;
  }
  std::string source_;
  std::shared_ptr<State> state_;  // shared: the parser copies the callback
};

// nlohmann's message without its "[json.exception.parse_error.101] " tag.
std::string json_message(const Json::exception& e) {
  std::string m = e.what();
  if (m.rfind("[json.exception.", 0) == 0)
    if (const std::size_t end = m.find("] "); end != std::string::npos) m.erase(0, end + 2);
  return m;
}

const Json& field(const Json& object, const std::string& key, const std::string& path, const std::string& source) {
  const auto it = object.find(key);
  if (it == object.end()) fail(source, path + key, "missing");
  return *it;
}

void only_keys(const Json& object, const std::set<std::string>& keys, const std::string& path,
               const std::string& source) {
  for (const auto& [key, value] : object.items()) {
    (void)value;
    if (!keys.count(key)) fail(source, path + key, "unknown key");
  }
}

double finite_number(const Json& v, const std::string& path, const std::string& source) {
  if (!v.is_number()) fail(source, path, "must be a number");
  const double d = v.get<double>();
  if (!std::isfinite(d)) fail(source, path, "must be finite");
  return d;
}

std::vector<double> numbers(const Json& v, const std::string& path, const std::string& source) {
  if (!v.is_array()) fail(source, path, "must be an array of numbers");
  std::vector<double> out;
  for (std::size_t k = 0; k < v.size(); ++k)
    out.push_back(finite_number(v[k], path + "[" + std::to_string(k) + "]", source));
  return out;
}

gl::ShadowMethod method_field(const Json& v, const std::string& path, const std::string& source) {
  if (!v.is_string()) fail(source, path, "must be a method name");
  const auto m = gl::shadow_method_from_string(v.get<std::string>());
  if (!m)
    fail(source, path,
         "'" + v.get<std::string>() + "' is not a method (zpass, zfail, zpplus, zpplus-corrected, preload)");
  return *m;
}

// A cost coefficient: a finite number, not negative.
double cost_number(const Json& object, const std::string& key, const std::string& path, const std::string& source) {
  const double v = finite_number(field(object, key, path, source), path + key, source);
  if (v < 0) fail(source, path + key, "must not be negative (a cost)");
  return v;
}

const Json& object_field(const Json& object, const std::string& key, const std::string& path,
                         const std::string& source) {
  const Json& v = field(object, key, path, source);
  if (!v.is_object()) fail(source, path + key, "must be an object");
  return v;
}

// The "device_profile" object; `path` is the prefix its fields are named
// with ("device_profile." in a policy, "" on its own).
DeviceProfile device_profile_of(const Json& j, const std::string& path, const std::string& source) {
  if (!j.is_object()) fail(source, path.empty() ? "(top level)" : path.substr(0, path.size() - 1), "must be an object");
  only_keys(j, {"gl_renderer", "origin", "passes", "cpu"}, path, source);
  DeviceProfile d;
  const Json& renderer = field(j, "gl_renderer", path, source);
  if (!renderer.is_string())
    fail(source, path + "gl_renderer", "must be a string (the GL_RENDERER it was measured on)");
  d.gl_renderer = renderer.get<std::string>();
  const Json& origin = field(j, "origin", path, source);
  if (!origin.is_string() || (origin != "calibrated" && origin != "hand" && origin != "scaled"))
    fail(source, path + "origin", "must be \"calibrated\", \"hand\" or \"scaled\"");
  d.origin = origin.get<std::string>();
  const Json& passes = object_field(j, "passes", path, source);
  const std::set<std::string> kinds(kPassKindNames.begin(), kPassKindNames.end());
  only_keys(passes, kinds, path + "passes.", source);
  for (std::size_t k = 0; k < kPassKindCount; ++k) {
    const std::string name(kPassKindNames[k]);
    const std::string at = path + "passes." + name + ".";
    const Json& pass = object_field(passes, name, path + "passes.", source);
    only_keys(pass, {"intercept_ms", "ms_per_mtriangle", "ms_per_mfragment"}, at, source);
    d.passes[k].intercept_ms = cost_number(pass, "intercept_ms", at, source);
    d.passes[k].ms_per_mtriangle = cost_number(pass, "ms_per_mtriangle", at, source);
    d.passes[k].ms_per_mfragment = cost_number(pass, "ms_per_mfragment", at, source);
  }
  const Json& cpu = object_field(j, "cpu", path, source);
  const std::string at = path + "cpu.";
  only_keys(cpu, {"ms_per_ktriangle_silhouette", "ms_per_ktriangle_clipped_cap", "ms_per_ktriangle_exact_test"}, at,
            source);
  d.cpu.ms_per_ktriangle_silhouette = cost_number(cpu, "ms_per_ktriangle_silhouette", at, source);
  d.cpu.ms_per_ktriangle_clipped_cap = cost_number(cpu, "ms_per_ktriangle_clipped_cap", at, source);
  d.cpu.ms_per_ktriangle_exact_test = cost_number(cpu, "ms_per_ktriangle_exact_test", at, source);
  return d;
}

Json device_profile_json(const DeviceProfile& d) {
  Json passes = Json::object();
  for (std::size_t k = 0; k < kPassKindCount; ++k)
    passes[std::string(kPassKindNames[k])] = {{"intercept_ms", d.passes[k].intercept_ms},
                                              {"ms_per_mtriangle", d.passes[k].ms_per_mtriangle},
                                              {"ms_per_mfragment", d.passes[k].ms_per_mfragment}};
  return {{"gl_renderer", d.gl_renderer},
          {"origin", d.origin},
          {"passes", passes},
          {"cpu",
           {{"ms_per_ktriangle_silhouette", d.cpu.ms_per_ktriangle_silhouette},
            {"ms_per_ktriangle_clipped_cap", d.cpu.ms_per_ktriangle_clipped_cap},
            {"ms_per_ktriangle_exact_test", d.cpu.ms_per_ktriangle_exact_test}}}};
}

// Text to JSON with the policy's strictness: duplicate keys are Schema
// errors, text that is not JSON a Parse error naming where.
Json parse_json(const std::string& text, const std::string& source) {
  const KeyTracker tracker(source);
  try {
    return Json::parse(text, tracker);
  } catch (const Json::exception& e) {
    // parse_error (syntax, ill-formed UTF-8: its message has the line and
    // column) and out_of_range (a number beyond double, 1e999).
    throw Error(ErrorKind::Parse, source + ": " + tracker.path() + ": not JSON: " + json_message(e));
  }
}

}  // namespace

double policy_feature(std::string_view name, const ConditioningFeatures& f) {
  if (!f.light_frustum_defined) return kNaN;
  if (name == "log_light_near_distance") return log10_or_nan(f.light_near_distance);
  if (name == "log_l_far_over_width") return log10_or_nan(f.l_far_over_width);
  if (name == "log_delta_over_width") return log10_or_nan(f.delta_over_width);
  if (name == "log_skew") return log10_or_nan(f.skew);
  if (name == "log_cond_light_transform") return log10_or_nan(f.cond_light_transform);
  if (name == "log_cap_window_error_px") return log10_or_nan(f.cap_window_error_px);
  if (name == "log_coordinate_over_size") return log10_or_nan(f.coordinate_over_size);
  if (name == "l_near_over_l_far") return f.l_near_over_l_far;
  throw Error(ErrorKind::Usage, "unknown policy feature '" + std::string(name) + "'");
}

bool cheap_policy_feature(std::string_view name) {
  return name == "log_light_near_distance" || name == "log_l_far_over_width" || name == "log_delta_over_width" ||
         name == "log_skew";
}

ConditioningFeatures cheap_conditioning_features(const CameraSpaceScene& cs, std::size_t light) {
  const Scene& scene = cs.scene();
  const Frustum& fr = scene.camera.frustum;
  ConditioningFeatures f;
  f.light_near_distance = to_double(Rational((cs.exact_light(light).z + Rational(fr.near)) / Rational(fr.near)));
  // The float light frustum's l_far and offset, as gl::light_frustum has them.
  const gl::Vec4f delta = gl::light_in_camera_space(scene, light);
  const float side = delta.z + static_cast<float>(fr.near);
  f.light_frustum_defined = side != 0.0f;
  if (!f.light_frustum_defined) return f;
  const double l_far = std::fabs(static_cast<double>(side));
  const double width = fr.right - fr.left;
  const double cx = 0.5 * (fr.left + fr.right), cy = 0.5 * (fr.bottom + fr.top);
  const double offset = std::hypot(delta.x - cx, delta.y - cy);
  f.l_far_over_width = l_far / width;
  f.delta_over_width = offset / width;
  f.skew = offset / l_far;
  return f;
}

double CrackModel::probability(const ConditioningFeatures& f) const {
  double z = bias;
  for (std::size_t k = 0; k < features.size(); ++k) {
    const double x = policy_feature(features[k], f);
    if (!std::isfinite(x)) return kNaN;
    z += weights[k] * (x - mean[k]) / scale[k];
  }
  return 1.0 / (1.0 + std::exp(-z));
}

DeviceProfile parse_device_profile(const std::string& text, const std::string& source) {
  return device_profile_of(parse_json(text, source), "", source);
}

std::string device_profile_to_json(const DeviceProfile& profile) {
  // The renderer string comes from the GL: one that is not UTF-8 gets U+FFFD.
  return device_profile_json(profile).dump(1, ' ', false, Json::error_handler_t::replace) + "\n";
}

DeviceProfile scaled_profile(const DeviceProfile& p, double gl_factor, double cpu_factor) {
  if (!(std::isfinite(gl_factor) && gl_factor > 0) || !(std::isfinite(cpu_factor) && cpu_factor > 0))
    throw Error(ErrorKind::Usage, "a profile's speed-up factors must be finite and positive (GL " +
                                      std::to_string(gl_factor) + ", CPU " + std::to_string(cpu_factor) + ")");
  DeviceProfile s = p;
  s.origin = "scaled";
  for (PassCost& c : s.passes) {
    c.intercept_ms /= gl_factor;
    c.ms_per_mtriangle /= gl_factor;
    c.ms_per_mfragment /= gl_factor;
  }
  s.cpu.ms_per_ktriangle_silhouette /= cpu_factor;
  s.cpu.ms_per_ktriangle_clipped_cap /= cpu_factor;
  s.cpu.ms_per_ktriangle_exact_test /= cpu_factor;
  return s;
}

SwitchPolicy parse_policy(const std::string& text, const std::string& source) {
  const Json j = parse_json(text, source);
  if (!j.is_object()) fail(source, "(top level)", "must be an object");
  only_keys(j,
            {"format", "version", "capped_method", "fallback_method", "switch_clamp", "zpass_far", "light_projection",
             "exact_zpass", "depth", "depth_mapping", "near_plane", "crack_model", "cost_models", "device_profile",
             "provenance"},
            "", source);
  const Json& format = field(j, "format", "", source);
  if (format != "nearcap-policy") fail(source, "format", "must be \"nearcap-policy\"");
  const Json& version = field(j, "version", "", source);
  if (!version.is_number_integer()) fail(source, "version", "must be an integer");
  const long long file_version = version.get<long long>();
  if (file_version < 1 || file_version > kPolicyVersion)
    fail(source, "version",
         std::to_string(file_version) + " is not a version this nearcap reads (1 to " + std::to_string(kPolicyVersion) +
             ")");
  SwitchPolicy p;
  if (const auto it = j.find("light_projection"); it != j.end()) {
    if (file_version < 2) fail(source, "light_projection", "is a version 2 field (this file says version 1)");
    if (!it->is_string() || !gl::light_projection_from_string(it->get<std::string>()))
      fail(source, "light_projection", "must be paper, glfrustum, composed, rebased or clipped-sides");
    p.light_projection = *gl::light_projection_from_string(it->get<std::string>());
  }
  if (const auto it = j.find("exact_zpass"); it != j.end()) {
    if (file_version < 2) fail(source, "exact_zpass", "is a version 2 field (this file says version 1)");
    if (!it->is_boolean()) fail(source, "exact_zpass", "must be true or false");
    p.exact_zpass = it->get<bool>();
  }
  if (const auto it = j.find("depth"); it != j.end()) {
    if (file_version < 3)
      fail(source, "depth", "is a version 3 field (this file says version " + std::to_string(file_version) + ")");
    if (!it->is_string() || (*it != "fixed24" && *it != "float32"))
      fail(source, "depth", "must be \"fixed24\" or \"float32\"");
    p.depth = *it == "fixed24" ? gl::DepthFormat::Fixed24 : gl::DepthFormat::Float32;
  }
  if (const auto it = j.find("depth_mapping"); it != j.end()) {
    if (file_version < 3)
      fail(source, "depth_mapping",
           "is a version 3 field (this file says version " + std::to_string(file_version) + ")");
    if (!it->is_string() || !gl::depth_mapping_from_string(it->get<std::string>()))
      fail(source, "depth_mapping", "must be \"standard\" or \"reversed\"");
    p.depth_mapping = *gl::depth_mapping_from_string(it->get<std::string>());
  }
  if (const auto it = j.find("near_plane"); it != j.end()) {
    if (file_version < 3)
      fail(source, "near_plane", "is a version 3 field (this file says version " + std::to_string(file_version) + ")");
    if (!it->is_string() || !gl::near_plane_from_string(it->get<std::string>()))
      fail(source, "near_plane", "must be \"scene\" or \"tight\"");
    p.near_plane = *gl::near_plane_from_string(it->get<std::string>());
  }
  p.capped_method = method_field(field(j, "capped_method", "", source), "capped_method", source);
  p.fallback_method = method_field(field(j, "fallback_method", "", source), "fallback_method", source);
  if (gl::uses_near_cap(p.fallback_method) || p.fallback_method == gl::ShadowMethod::ZPass)
    fail(source, "fallback_method", "must be zfail or preload (a method right without a near-cap)");
  if (p.capped_method == gl::ShadowMethod::ZPass)
    fail(source, "capped_method", "must not be zpass (it is wrong for the occluders that meet the light pyramid)");
  if (p.capped_method == gl::ShadowMethod::Preload && gl::uses_near_cap(p.fallback_method))
    fail(source, "capped_method", "preload cannot share a frame with a ZP+ method");
  if (!p.exact_zpass && !gl::uses_near_cap(p.capped_method))
    fail(source, "exact_zpass", "false needs a ZP+ capped method (zpplus or zpplus-corrected)");
  if (p.near_plane == gl::NearPlane::Tight && p.exact_zpass)
    fail(source, "near_plane",
         "tight needs exact_zpass false (the exact Z-pass test decides for the scene's near plane)");
  const Json& clamp = field(j, "switch_clamp", "", source);
  if (!clamp.is_string() || !gl::switch_clamp_from_string(clamp.get<std::string>()))
    fail(source, "switch_clamp", "must be \"clamp\", \"clamp-far\" or \"far-cap\"");
  p.switch_clamp = *gl::switch_clamp_from_string(clamp.get<std::string>());
  const Json& zpass_far = field(j, "zpass_far", "", source);
  if (!zpass_far.is_string() || !gl::zpass_far_from_string(zpass_far.get<std::string>()))
    fail(source, "zpass_far", "must be \"finite\" or \"infinite\"");
  p.zpass_far = *gl::zpass_far_from_string(zpass_far.get<std::string>());
  const Json& m = field(j, "crack_model", "", source);
  if (!m.is_object()) fail(source, "crack_model", "must be an object");
  only_keys(m, {"features", "mean", "scale", "weights", "bias", "threshold"}, "crack_model.", source);
  const Json& names = field(m, "features", "crack_model.", source);
  if (!names.is_array()) fail(source, "crack_model.features", "must be an array of feature names");
  for (std::size_t k = 0; k < names.size(); ++k) {
    const std::string path = "crack_model.features[" + std::to_string(k) + "]";
    if (!names[k].is_string()) fail(source, path, "must be a feature name");
    const std::string name = names[k].get<std::string>();
    bool known = false;
    for (std::string_view f : kPolicyFeatures) known = known || f == name;
    if (!known) fail(source, path, "'" + name + "' is not a policy feature");
    if (std::find(p.crack_model.features.begin(), p.crack_model.features.end(), name) != p.crack_model.features.end())
      fail(source, path, "'" + name + "' appears twice (each feature once)");
    p.crack_model.features.push_back(name);
  }
  p.crack_model.mean = numbers(field(m, "mean", "crack_model.", source), "crack_model.mean", source);
  p.crack_model.scale = numbers(field(m, "scale", "crack_model.", source), "crack_model.scale", source);
  p.crack_model.weights = numbers(field(m, "weights", "crack_model.", source), "crack_model.weights", source);
  const std::size_t n = p.crack_model.features.size();
  for (const auto& [name, v] : {std::pair<const char*, const std::vector<double>*>{"mean", &p.crack_model.mean},
                                {"scale", &p.crack_model.scale},
                                {"weights", &p.crack_model.weights}})
    if (v->size() != n)
      fail(source, std::string("crack_model.") + name,
           std::to_string(v->size()) + " values for " + std::to_string(n) + " features");
  for (std::size_t k = 0; k < n; ++k)
    if (!(p.crack_model.scale[k] > 0)) fail(source, "crack_model.scale[" + std::to_string(k) + "]", "must be positive");
  p.crack_model.bias = finite_number(field(m, "bias", "crack_model.", source), "crack_model.bias", source);
  p.crack_model.threshold =
      finite_number(field(m, "threshold", "crack_model.", source), "crack_model.threshold", source);
  if (!(p.crack_model.threshold > 0 && p.crack_model.threshold <= 1))
    fail(source, "crack_model.threshold", "must be in (0, 1]");
  {
    const Json& costs = field(j, "cost_models", "", source);
    if (!costs.is_object()) fail(source, "cost_models", "must be an object of methods");
    for (const auto& [name, model] : costs.items()) {
      const std::string path = "cost_models." + name;
      const auto method = gl::shadow_method_from_string(name);
      if (!method) fail(source, path, "'" + name + "' is not a method");
      if (!model.is_object()) fail(source, path, "must be an object");
      only_keys(model, {"intercept_ms", "ms_per_mtriangle", "ms_per_mfragment"}, path + ".", source);
      CostModel cm;
      cm.intercept_ms = finite_number(field(model, "intercept_ms", path + ".", source), path + ".intercept_ms", source);
      cm.ms_per_mtriangle =
          finite_number(field(model, "ms_per_mtriangle", path + ".", source), path + ".ms_per_mtriangle", source);
      cm.ms_per_mfragment =
          finite_number(field(model, "ms_per_mfragment", path + ".", source), path + ".ms_per_mfragment", source);
      p.cost_models.emplace_back(*method, cm);
    }
  }
  if (const auto it = j.find("device_profile"); it != j.end()) {
    if (file_version < 4)
      fail(source, "device_profile",
           "is a version 4 field (this file says version " + std::to_string(file_version) + ")");
    p.device_profile = device_profile_of(*it, "device_profile.", source);
  }
  const Json& provenance = field(j, "provenance", "", source);
  if (!provenance.is_object()) fail(source, "provenance", "must be an object");
  p.provenance_json = provenance.dump();
  return p;
}

SwitchPolicy load_policy(const std::string& path) {
  return parse_policy(io::read_input_file(path, "policy file"), path);
}

std::string policy_to_json(const SwitchPolicy& p) {
  Json j;
  j["format"] = "nearcap-policy";
  j["version"] = kPolicyVersion;
  j["capped_method"] = std::string(gl::to_string(p.capped_method));
  j["fallback_method"] = std::string(gl::to_string(p.fallback_method));
  j["switch_clamp"] = std::string(gl::to_string(p.switch_clamp));
  j["zpass_far"] = std::string(gl::to_string(p.zpass_far));
  j["light_projection"] = std::string(gl::to_string(p.light_projection));
  j["exact_zpass"] = p.exact_zpass;
  if (p.depth) j["depth"] = std::string(name_of(*p.depth));
  if (p.depth_mapping) j["depth_mapping"] = std::string(gl::to_string(*p.depth_mapping));
  if (p.near_plane) j["near_plane"] = std::string(gl::to_string(*p.near_plane));
  Json m;
  m["features"] = p.crack_model.features;
  m["mean"] = p.crack_model.mean;
  m["scale"] = p.crack_model.scale;
  m["weights"] = p.crack_model.weights;
  m["bias"] = p.crack_model.bias;
  m["threshold"] = p.crack_model.threshold;
  j["crack_model"] = m;
  Json costs = Json::object();
  for (const auto& [method, cm] : p.cost_models)
    costs[std::string(gl::to_string(method))] = {{"intercept_ms", cm.intercept_ms},
                                                 {"ms_per_mtriangle", cm.ms_per_mtriangle},
                                                 {"ms_per_mfragment", cm.ms_per_mfragment}};
  j["cost_models"] = costs;
  if (p.device_profile) j["device_profile"] = device_profile_json(*p.device_profile);
  j["provenance"] = Json::parse(p.provenance_json);
  // The provenance names files: a name that is not UTF-8 gets U+FFFD.
  return j.dump(1, ' ', false, Json::error_handler_t::replace) + "\n";
}

namespace {
PolicyDecision decide_by_cost(const SwitchPolicy& policy, const CameraSpaceScene& cs, std::size_t light,
                              const gl::EmulationSettings& base, PolicyDecision d);
}  // namespace

PolicyDecision decide(const SwitchPolicy& policy, const CameraSpaceScene& cs, std::size_t light,
                      const gl::EmulationSettings& base) {
  const auto t0 = std::chrono::steady_clock::now();
  const Scene& scene = cs.scene();
  PolicyDecision d;
  d.settings = base;
  d.settings.switch_clamp = policy.switch_clamp;
  d.settings.zpass_far = policy.zpass_far;
  d.settings.light_frustum.projection = policy.light_projection;
  if (policy.depth) d.settings.depth = *policy.depth;
  if (policy.near_plane) d.settings.near_plane = *policy.near_plane;
  if (policy.depth_mapping) {
    d.settings.depth_mapping = *policy.depth_mapping;
    // The reversed row puts infinity at depth 0 exactly; the nudges are the standard row's.
    if (*policy.depth_mapping == gl::DepthMapping::Reversed) d.settings.infinite_far = gl::InfiniteFar::Exact;
  }
  // The clipped-sides near-cap needs no light frustum: ZP+ with it stays
  // right where the paper's frustum is undefined.
  const bool frustum_free =
      gl::uses_near_cap(policy.capped_method) && policy.light_projection == gl::LightProjection::ClippedSides;
  const double near =
      d.settings.near_plane == gl::NearPlane::Tight ? gl::tight_frustum(scene).near : scene.camera.frustum.near;
  d.depth_step_over_size = depth_step_over_size(cs, near, d.settings.depth, d.settings.depth_mapping);
  d.depth_limited = d.depth_step_over_size >= kDepthLimitedStep;
  if (d.depth_limited) {
    char note[512];
    std::snprintf(note, sizeof note,
                  "depth-limited: one depth step spans %.3g of the scene's size at its farthest point (near plane "
                  "%.3g): surfaces that close share a depth value, and no method is guaranteed right (Z-fail "
                  "cracks in about a third of such sampled frames); reversed-Z with a float depth buffer (--depth "
                  "float32 --depth-mapping reversed) or the tight near plane (--near-plane tight) fixes it",
                  d.depth_step_over_size, near);
    d.depth_note = note;
  }
  d.object_methods.assign(scene.objects.size(), gl::ShadowMethod::ZPass);
  d.reasons.assign(scene.objects.size(), "");
  d.crack_probability = kNaN;
  if (policy.exact_zpass && d.settings.near_plane == gl::NearPlane::Tight)
    throw Error(ErrorKind::Usage,
                "the policy's exact Z-pass test decides for the scene's near plane, and the frame would use the tight "
                "one: a tight near plane needs a policy with exact_zpass false");
  if (policy.device_profile) {
    d = decide_by_cost(policy, cs, light, base, std::move(d));
    d.decide_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return d;
  }
  if (!policy.exact_zpass) {
    // No per-occluder test: the capped method everywhere (with the
    // clipped-sides cap that is Z-pass plus the cap its own clipped sides
    // leave, nothing where they leave none).
    for (std::size_t o = 0; o < scene.objects.size(); ++o)
      if (scene.objects[o].occluder) {
        d.object_methods[o] = policy.capped_method;
        d.reasons[o] = "every occluder (no exact Z-pass test)";
      }
    d.decide_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return d;
  }
  std::vector<bool> meets;
  bool degenerate = false;
  try {
    meets = occluders_meeting_light_pyramid(cs, light);
  } catch (const Error& e) {
    if (e.kind() != ErrorKind::Degenerate) throw;
    degenerate = true;  // the light in the near plane
  }
  bool any_capped = false;
  for (std::size_t o = 0; o < scene.objects.size(); ++o) {
    if (!scene.objects[o].occluder) continue;
    if (degenerate && frustum_free) {
      d.object_methods[o] = policy.capped_method;
      d.reasons[o] = "the light lies in the near plane: the clipped-sides near-cap needs no light frustum";
    } else if (degenerate) {
      d.object_methods[o] = policy.fallback_method;
      d.reasons[o] = "the light lies in the near plane: no light frustum";
    } else if (!meets[o]) {
      d.reasons[o] = "exact: meets no point of the light pyramid (empty near-cap)";
    } else {
      any_capped = true;
    }
  }
  if (any_capped) {
    gl::ShadowMethod chosen = policy.capped_method;
    std::string why;
    if (gl::uses_near_cap(chosen)) {
      // A model of cheap features alone needs neither the light frustum's
      // l_near (a pass over the occluders) nor the window errors.
      bool cheap = true;
      for (const std::string& name : policy.crack_model.features) cheap = cheap && cheap_policy_feature(name);
      gl::LightFrustum lf;
      ConditioningFeatures f;
      if (cheap) {
        f = cheap_conditioning_features(cs, light);
        lf.defined = f.light_frustum_defined;
        lf.undefined_reason = "the light lies in the camera's near plane (l_far = 0)";
      } else {
        lf = gl::light_frustum(scene, light, base.light_frustum);
        if (lf.defined) f = conditioning_features(cs, light, lf, base.arithmetic);
      }
      if (!lf.defined && !frustum_free) {
        chosen = policy.fallback_method;
        why = "meets the light pyramid, no light frustum (" + lf.undefined_reason + ")";
      } else {
        d.crack_probability = policy.crack_model.probability(f);
        if (!(d.crack_probability < policy.crack_model.threshold)) {
          chosen = policy.fallback_method;
          why = "meets the light pyramid, crack predicted (P = " + std::to_string(d.crack_probability) + ")";
        } else {
          why = "meets the light pyramid, no crack predicted (P = " + std::to_string(d.crack_probability) + ")";
        }
      }
    } else {
      why = "meets the light pyramid";
    }
    for (std::size_t o = 0; o < scene.objects.size(); ++o)
      if (scene.objects[o].occluder && !degenerate && meets[o]) {
        d.object_methods[o] = chosen;
        d.reasons[o] = why;
      }
  }
  d.decide_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return d;
}

namespace {

// The decision's own helpers (the cost decision, switch_policy.hpp).

// A profile's price of one occluder's work, its passes' intercepts left out
// (a pass is drawn once per frame whatever its occluders: the frame's total
// counts each intercept once).
double marginal_ms(const DeviceProfile& profile, FrameWork w) {
  w.drawn = {};
  return profile.predict_ms(w);
}

std::string ms_text(double ms) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", ms);
  return buf;
}

// Whether the policy's capped method with the paper's cap is a candidate in
// this (frame, light): the light frustum exists and the crack model predicts
// no crack; `why` says why not, `probability` is the model's.
bool paper_cap_admitted(const SwitchPolicy& policy, const CameraSpaceScene& cs, std::size_t light,
                        const gl::EmulationSettings& base, double& probability, std::string& why) {
  probability = kNaN;
  if (!gl::uses_near_cap(policy.capped_method) || policy.light_projection == gl::LightProjection::ClippedSides) {
    why = "the policy's crack model is not the paper cap's";
    return false;
  }
  bool cheap = true;
  for (const std::string& name : policy.crack_model.features) cheap = cheap && cheap_policy_feature(name);
  ConditioningFeatures f;
  bool defined = false;
  if (cheap) {
    f = cheap_conditioning_features(cs, light);
    defined = f.light_frustum_defined;
  } else {
    const gl::LightFrustum lf = gl::light_frustum(cs.scene(), light, base.light_frustum);
    defined = lf.defined;
    if (defined) f = conditioning_features(cs, light, lf, base.arithmetic);
  }
  if (!defined) {
    why = "no light frustum";
    return false;
  }
  probability = policy.crack_model.probability(f);
  if (!(probability < policy.crack_model.threshold)) {
    why = "crack predicted (P = " + ms_text(probability) + ")";
    return false;
  }
  return true;
}

PolicyDecision decide_by_cost(const SwitchPolicy& policy, const CameraSpaceScene& cs, std::size_t light,
                              const gl::EmulationSettings& base, PolicyDecision d) {
  const DeviceProfile& profile = *policy.device_profile;
  const Scene& scene = cs.scene();
  const CandidateMethod zpass{gl::ShadowMethod::ZPass, gl::LightProjection::Paper};
  const CandidateMethod zfail{gl::ShadowMethod::ZFail, gl::LightProjection::Paper};
  const CandidateMethod clipped{gl::ShadowMethod::ZPPlus, gl::LightProjection::ClippedSides};
  const CandidateMethod paper{policy.capped_method, gl::LightProjection::Paper};

  // The light in the near plane (exactly): no pyramid test, no light frustum.
  const bool light_on_near_plane = cheap_conditioning_features(cs, light).light_near_distance == 0;
  std::string paper_why;
  const bool paper_ok =
      !light_on_near_plane && paper_cap_admitted(policy, cs, light, base, d.crack_probability, paper_why);
  if (light_on_near_plane) paper_why = "the light lies in the near plane: no light frustum";

  struct Occluder {
    std::size_t object = 0;
    OccluderWorkInputs in;
    double zfail_ms = 0, clipped_ms = 0, paper_ms = kNaN, zpass_ms = 0;
    bool zpass_ok = false;  // the near-cap is empty (certainly, or by the exact test)
    std::string zpass_why;
  };
  std::vector<Occluder> occluders;
  for (std::size_t o = 0; o < scene.objects.size(); ++o) {
    if (!scene.objects[o].occluder) continue;
    Occluder oc;
    oc.object = o;
    oc.in = occluder_work_inputs(scene, o, light);
    oc.zfail_ms = marginal_ms(profile, occluder_work(oc.in, zfail));
    oc.clipped_ms = marginal_ms(profile, occluder_work(oc.in, clipped));
    if (paper_ok) oc.paper_ms = marginal_ms(profile, occluder_work(oc.in, paper));
    oc.zpass_ms = marginal_ms(profile, occluder_work(oc.in, zpass));
    occluders.push_back(std::move(oc));
  }
  // Z-pass: free where the cull is certain; elsewhere only after the exact
  // test, whose cost the frame then pays for every occluder it tests.
  std::vector<bool> untested(occluders.size(), false);
  bool any_untested = false;
  for (std::size_t i = 0; i < occluders.size(); ++i) {
    Occluder& oc = occluders[i];
    if (!policy.exact_zpass) {
      oc.zpass_why = "the policy has no exact Z-pass test";
    } else if (light_on_near_plane) {
      oc.zpass_why = "the light lies in the near plane";
    } else if (oc.in.certainly_misses_light_pyramid) {
      oc.zpass_ok = true;
      oc.zpass_why = "certainly misses the light pyramid (empty near-cap)";
    } else {
      untested[i] = any_untested = true;
    }
  }

  // The frame-level options, each with its cheapest candidate per occluder
  // (Z-pass where `zpass_allowed`), the best of them: its predicted ms, the
  // methods, the work, the light projection; `log` keeps each option's ms.
  struct Option {
    std::string name;
    gl::LightProjection projection;
    bool clipped = false, paper = false;
  };
  std::vector<Option> options{{"no near-cap", policy.light_projection, false, false},
                              {"clipped-sides cap", gl::LightProjection::ClippedSides, true, false}};
  if (paper_ok) options.push_back({"paper cap", policy.light_projection, false, true});
  const FrameWork shared = shared_frame_work(scene);
  struct Frame {
    double ms = kNaN;
    std::vector<CandidateMethod> choice;
    FrameWork work;
    gl::LightProjection projection = gl::LightProjection::Paper;
  };
  auto best_frame = [&](const std::vector<bool>& zpass_allowed, const FrameWork& extra,
                        std::vector<std::pair<std::string, double>>* log) {
    Frame best;
    for (const Option& option : options) {
      Frame f;
      f.work = shared;
      f.work += extra;
      f.projection = option.projection;
      for (std::size_t i = 0; i < occluders.size(); ++i) {
        const Occluder& oc = occluders[i];
        CandidateMethod c = zfail;
        double ms = oc.zfail_ms;
        if (option.clipped && oc.clipped_ms < ms) {
          c = clipped;
          ms = oc.clipped_ms;
        }
        if (option.paper && oc.paper_ms < ms) {
          c = paper;
          ms = oc.paper_ms;
        }
        if (zpass_allowed[i] && oc.zpass_ms <= ms) c = zpass;  // a tie: Z-pass, the simpler frame
        f.work += occluder_work(oc.in, c);
        f.choice.push_back(c);
      }
      f.ms = profile.predict_ms(f.work);
      if (log) log->push_back({option.name, f.ms});
      if (!(f.ms >= best.ms)) best = std::move(f);
    }
    return best;
  };
  std::vector<bool> allowed(occluders.size(), false);
  for (std::size_t i = 0; i < occluders.size(); ++i) allowed[i] = occluders[i].zpass_ok;
  Frame chosen = best_frame(allowed, {}, &d.predicted_options);
  if (any_untested) {
    // The test runs when the frame it could give at best, Z-pass for every
    // occluder it tests and the test paid, beats the frame without it.
    FrameWork test_work;
    std::vector<bool> optimistic = allowed;
    for (std::size_t i = 0; i < occluders.size(); ++i)
      if (untested[i]) {
        test_work.exact_test_triangles += occluders[i].in.triangles;
        optimistic[i] = true;
      }
    const double test_ms = profile.cpu_ms(test_work);
    if (best_frame(optimistic, test_work, nullptr).ms < chosen.ms) {
      const std::vector<bool> meets = occluders_meeting_light_pyramid(cs, light);
      for (std::size_t i = 0; i < occluders.size(); ++i) {
        if (!untested[i]) continue;
        Occluder& oc = occluders[i];
        oc.zpass_ok = allowed[i] = !meets[oc.object];
        oc.zpass_why = (oc.zpass_ok ? "exact: meets no point of the light pyramid (empty near-cap)"
                                    : "meets the light pyramid (exact test)") +
                       std::string("; the frame's test ") + ms_text(test_ms) + " ms";
      }
      d.predicted_options.clear();
      chosen = best_frame(allowed, test_work, &d.predicted_options);
    } else {
      for (std::size_t i = 0; i < occluders.size(); ++i)
        if (untested[i])
          occluders[i].zpass_why =
              "exact test not run (its predicted cost, " + ms_text(test_ms) + " ms for the frame, above the saving)";
    }
  }
  const double best_total = chosen.ms;
  const std::vector<CandidateMethod>& best_choice = chosen.choice;
  d.predicted_work = chosen.work;
  d.settings.light_frustum.projection = chosen.projection;
  d.predicted_ms = best_total;
  for (std::size_t k = 0; k < occluders.size(); ++k) {
    const Occluder& oc = occluders[k];
    const CandidateMethod& c = best_choice[k];
    d.object_methods[oc.object] = c.method;
    std::string why = "cost: " + c.name() + "; predicted ms: zfail " + ms_text(oc.zfail_ms) + ", " + clipped.name() +
                      " " + ms_text(oc.clipped_ms) + ", " + paper.name() + " " +
                      (paper_ok ? ms_text(oc.paper_ms) : "not a candidate (" + paper_why + ")") + ", zpass " +
                      (oc.zpass_ok ? ms_text(oc.zpass_ms) : "not a candidate") + " (" + oc.zpass_why + ")";
    d.reasons[oc.object] = why;
  }
  return d;
}

}  // namespace

}  // namespace nearcap::analysis
