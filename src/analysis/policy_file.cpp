// The policy file (see switch_policy.hpp): reading and writing policy.json
// and its device profile; the decision that uses them is switch_policy.cpp.
#include "nearcap/analysis/switch_policy.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "nearcap/io/input_files.hpp"
#include "nearcap/io/json_reader.hpp"

namespace nearcap::analysis {
namespace {

using Json = nlohmann::json;
using io::JsonValue;

gl::ShadowMethod method_field(const JsonValue& v) { return v.named<gl::ShadowMethod>(); }

// A CPU task's cost (device_profile.hpp, CpuTaskCost), by its JSON keys.
// ms_per_kexamined may be absent (0): profiles fitted before the cull's
// examined faces were counted price the same work as before.
const std::vector<std::string_view> kCpuTaskCostKeys{"intercept_ms",   "ms_per_ktriangle",   "ms_per_kreaching",
                                                     "ms_per_ktested", "ms_per_kstraddling", "ms_per_kexamined"};

// A cost coefficient: a finite number of milliseconds, not negative, and at
// most kMaxCostCoefficientMs (device_profile.hpp).
double cost_number(const JsonValue& object, std::string_view key) {
  static_assert(kMaxCostCoefficientMs == 1e6, "the message below names the bound");
  const JsonValue v = object.at(key);
  const double d = v.number();
  if (d < 0) v.fail("must not be negative (a cost)");
  if (d > kMaxCostCoefficientMs) v.fail("must be at most 1e6 (milliseconds)");
  return d;
}

DeviceProfile device_profile_of(const JsonValue& j) {
  j.only_keys({"gl_renderer", "origin", "passes", "frame", "cpu"});
  DeviceProfile d;
  d.gl_renderer = j.required<std::string>("gl_renderer");
  d.origin = j.at("origin").choice<std::string>({{"calibrated", "calibrated"}, {"hand", "hand"}, {"scaled", "scaled"}});
  const JsonValue passes = j.at("passes");
  std::vector<std::string_view> pass_keys(kPassKindNames.begin(), kPassKindNames.end());
  pass_keys.push_back(kEyeCountPassName);  // optional
  passes.only_keys(pass_keys);
  // ms_per_mtriangle_in_view is optional: a profile without it prices
  // each pass by its submitted triangles and fragments alone.
  auto pass_cost = [](const JsonValue& pass) {
    pass.only_keys({"intercept_ms", "ms_per_mtriangle", "ms_per_mfragment", "ms_per_mtriangle_in_view"});
    PassCost c{cost_number(pass, "intercept_ms"), cost_number(pass, "ms_per_mtriangle"),
               cost_number(pass, "ms_per_mfragment")};
    if (pass.find("ms_per_mtriangle_in_view"))
      c.ms_per_mtriangle_in_view = cost_number(pass, "ms_per_mtriangle_in_view");
    return c;
  };
  for (std::size_t k = 0; k < kPassKindCount; ++k) d.passes[k] = pass_cost(passes.at(kPassKindNames[k]));
  if (const auto eye = passes.find(kEyeCountPassName)) d.eye_count = pass_cost(*eye);
  if (const auto frame = j.find("frame")) {
    frame->only_keys({"intercept_ms", "ms_saved_per_pass"});
    d.frame = FrameCost{cost_number(*frame, "intercept_ms"), cost_number(*frame, "ms_saved_per_pass")};
    double smallest = INFINITY;
    for (const PassCost& c : d.passes) smallest = std::min(smallest, c.intercept_ms);
    if (d.eye_count) smallest = std::min(smallest, d.eye_count->intercept_ms);
    if (d.frame->ms_saved_per_pass > smallest)
      frame->at("ms_saved_per_pass")
          .fail("must not exceed the smallest pass intercept_ms (" + std::to_string(smallest) +
                "): a pass drawn in a frame would cost less than nothing");
  }
  const JsonValue cpu = j.at("cpu");
  d.cpu.ms_per_ktriangle_silhouette = cost_number(cpu, "ms_per_ktriangle_silhouette");
  if (cpu.find("ms_per_ktriangle_clipped_cap") || cpu.find("ms_per_ktriangle_exact_test")) {
    // The per-triangle layout: each task priced per thousand of the
    // triangles the decision priced it by, the counts' `tested`.
    cpu.only_keys({"ms_per_ktriangle_silhouette", "ms_per_ktriangle_clipped_cap", "ms_per_ktriangle_exact_test"});
    d.cpu.clipped_cap.ms_per_ktested = cost_number(cpu, "ms_per_ktriangle_clipped_cap");
    d.cpu.exact_test.ms_per_ktested = cost_number(cpu, "ms_per_ktriangle_exact_test");
    return d;
  }
  cpu.only_keys({"ms_per_ktriangle_silhouette", "clipped_cap", "exact_test"});
  for (const auto& [key, cost] :
       {std::pair{"clipped_cap", &d.cpu.clipped_cap}, std::pair{"exact_test", &d.cpu.exact_test}}) {
    const JsonValue task = cpu.at(key);
    task.only_keys(kCpuTaskCostKeys);
    *cost = {cost_number(task, "intercept_ms"), cost_number(task, "ms_per_ktriangle"),
             cost_number(task, "ms_per_kreaching"), cost_number(task, "ms_per_ktested"),
             cost_number(task, "ms_per_kstraddling")};
    cost->ms_per_kexamined = task.find("ms_per_kexamined") ? cost_number(task, "ms_per_kexamined") : 0.0;
  }
  return d;
}

Json cpu_task_cost_json(const CpuTaskCost& c) {
  return {{"intercept_ms", c.intercept_ms},
          {"ms_per_ktriangle", c.ms_per_ktriangle},
          {"ms_per_kreaching", c.ms_per_kreaching},
          {"ms_per_ktested", c.ms_per_ktested},
          {"ms_per_kstraddling", c.ms_per_kstraddling},
          {"ms_per_kexamined", c.ms_per_kexamined}};
}

Json device_profile_json(const DeviceProfile& d) {
  auto pass_json = [](const PassCost& c) {
    Json j{{"intercept_ms", c.intercept_ms},
           {"ms_per_mtriangle", c.ms_per_mtriangle},
           {"ms_per_mfragment", c.ms_per_mfragment}};
    if (c.ms_per_mtriangle_in_view != 0) j["ms_per_mtriangle_in_view"] = c.ms_per_mtriangle_in_view;
    return j;
  };
  Json passes = Json::object();
  for (std::size_t k = 0; k < kPassKindCount; ++k) passes[std::string(kPassKindNames[k])] = pass_json(d.passes[k]);
  if (d.eye_count) passes[std::string(kEyeCountPassName)] = pass_json(*d.eye_count);
  Json j{{"gl_renderer", d.gl_renderer},
         {"origin", d.origin},
         {"passes", passes},
         {"cpu",
          {{"ms_per_ktriangle_silhouette", d.cpu.ms_per_ktriangle_silhouette},
           {"clipped_cap", cpu_task_cost_json(d.cpu.clipped_cap)},
           {"exact_test", cpu_task_cost_json(d.cpu.exact_test)}}}};
  if (d.frame)
    j["frame"] = {{"intercept_ms", d.frame->intercept_ms}, {"ms_saved_per_pass", d.frame->ms_saved_per_pass}};
  return j;
}

}  // namespace

DeviceProfile parse_device_profile(const std::string& text, const std::string& source) {
  return device_profile_of(io::JsonDocument::parse(text, source).root());
}

std::string device_profile_to_json(const DeviceProfile& profile) {
  // The renderer string comes from the GL: one that is not UTF-8 gets U+FFFD.
  std::string text = device_profile_json(profile).dump(1, ' ', false, Json::error_handler_t::replace) + "\n";
  // What is written reads back: a profile its reader refuses (a coefficient
  // out of range, a NaN written as null) is this error, naming the field,
  // instead of a file no command reads.
  parse_device_profile(text, "the device profile to write");
  return text;
}

SwitchPolicy parse_policy(const std::string& text, const std::string& source) {
  const io::JsonDocument doc = io::JsonDocument::parse(text, source);
  const JsonValue j = doc.root();
  j.only_keys({"format", "version", "capped_method", "fallback_method", "switch_clamp", "zpass_far", "light_projection",
               "exact_zpass", "depth", "depth_mapping", "near_plane", "crack_model", "cost_models", "device_profile",
               "unpriced_frames", "provenance"});
  j.at("format").choice<bool>({{"nearcap-policy", true}});
  const JsonValue version = j.at("version");
  const long long file_version = version.integer();
  if (file_version < 1 || file_version > kPolicyVersion)
    version.fail(std::to_string(file_version) + " is not a version this nearcap reads (1 to " +
                 std::to_string(kPolicyVersion) + ")");
  // A field newer than the file's version.
  const auto since = [file_version](const JsonValue& v, long long field_version) {
    if (file_version < field_version)
      v.fail("is a version " + std::to_string(field_version) + " field (this file says version " +
             std::to_string(file_version) + ")");
  };
  SwitchPolicy p;
  if (const auto v = j.find("light_projection")) {
    since(*v, 2);
    p.light_projection = v->named<gl::LightProjection>();
  }
  if (const auto v = j.find("exact_zpass")) {
    since(*v, 2);
    p.exact_zpass = v->boolean();
  }
  if (const auto v = j.find("depth")) {
    since(*v, 3);
    p.depth = v->named<gl::DepthFormat>();
  }
  if (const auto v = j.find("depth_mapping")) {
    since(*v, 3);
    p.depth_mapping = v->named<gl::DepthMapping>();
  }
  if (const auto v = j.find("near_plane")) {
    since(*v, 3);
    p.near_plane = v->named<gl::NearPlane>();
  }
  p.capped_method = method_field(j.at("capped_method"));
  p.fallback_method = method_field(j.at("fallback_method"));
  if (p.fallback_method != gl::ShadowMethod::ZFail && p.fallback_method != gl::ShadowMethod::Preload)
    j.at("fallback_method").fail("must be zfail or preload (a method right without a near-cap)");
  if (p.capped_method == gl::ShadowMethod::ZPass)
    j.at("capped_method").fail("must not be zpass (it is wrong for the occluders that meet the light pyramid)");
  if (p.capped_method == gl::ShadowMethod::Preload && gl::uses_near_cap(p.fallback_method))
    j.at("capped_method").fail("preload cannot share a frame with a ZP+ method");
  if (!p.exact_zpass && !gl::uses_near_cap(p.capped_method))
    j.at("exact_zpass").fail("false needs a ZP+ capped method (zpplus or zpplus-corrected)");
  if (p.near_plane == gl::NearPlane::Tight && p.exact_zpass)
    j.at("near_plane").fail("tight needs exact_zpass false (the exact Z-pass test decides for the scene's near plane)");
  p.switch_clamp = j.at("switch_clamp").named<gl::SwitchClamp>();
  p.zpass_far = j.at("zpass_far").named<gl::ZPassFar>();
  const JsonValue m = j.at("crack_model");
  m.only_keys({"features", "mean", "scale", "weights", "bias", "threshold"});
  const JsonValue names = m.at("features");
  if (!names.is_array()) names.fail("expected an array of feature names, found " + std::string(names.type_name()));
  for (const JsonValue& f : names.elements()) {
    const std::string name = f.string();
    bool known = false;
    for (std::string_view k : kPolicyFeatures) known = known || k == name;
    if (!known) f.fail("'" + name + "' is not a policy feature");
    if (std::find(p.crack_model.features.begin(), p.crack_model.features.end(), name) != p.crack_model.features.end())
      f.fail("'" + name + "' appears twice (each feature once)");
    p.crack_model.features.push_back(name);
  }
  p.crack_model.mean = m.at("mean").numbers();
  p.crack_model.scale = m.at("scale").numbers();
  p.crack_model.weights = m.at("weights").numbers();
  const std::size_t n = p.crack_model.features.size();
  for (const auto& [name, v] : {std::pair<const char*, const std::vector<double>*>{"mean", &p.crack_model.mean},
                                {"scale", &p.crack_model.scale},
                                {"weights", &p.crack_model.weights}})
    if (v->size() != n) m.at(name).fail(std::to_string(v->size()) + " values for " + std::to_string(n) + " features");
  for (std::size_t k = 0; k < n; ++k)
    if (!(p.crack_model.scale[k] > 0)) m.at("scale").elements()[k].fail("must be positive");
  p.crack_model.bias = m.required<double>("bias");
  const JsonValue threshold = m.at("threshold");
  p.crack_model.threshold = threshold.number();
  if (!(p.crack_model.threshold > 0 && p.crack_model.threshold <= 1)) threshold.fail("must be in (0, 1]");
  // By name, whatever order the file has them in.
  auto cost_models = j.at("cost_models").members();
  std::sort(cost_models.begin(), cost_models.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& [name, model] : cost_models) {
    const auto method = gl::shadow_method_from_string(name);
    if (!method) model.fail("'" + name + "' is not a method");
    model.only_keys({"intercept_ms", "ms_per_mtriangle", "ms_per_mfragment"});
    CostModel cm;
    cm.intercept_ms = model.required<double>("intercept_ms");
    cm.ms_per_mtriangle = model.required<double>("ms_per_mtriangle");
    cm.ms_per_mfragment = model.required<double>("ms_per_mfragment");
    p.cost_models.emplace_back(*method, cm);
  }
  if (const auto v = j.find("device_profile")) {
    since(*v, 4);
    p.device_profile = device_profile_of(*v);
  }
  if (const auto v = j.find("unpriced_frames")) {
    since(*v, 5);
    if (!p.device_profile) v->fail("needs a device_profile (it names the frames the cost decision does not price)");
    // Its tiers (version 6), or one tier as the object alone (version 5).
    if (v->is_array()) since(*v, 6);
    const std::vector<JsonValue> tiers = v->is_array() ? v->elements() : std::vector<JsonValue>{*v};
    if (tiers.empty()) v->fail("expected at least one tier (leave the field out to price every frame)");
    for (const JsonValue& t : tiers) {
      t.only_keys({"max_occluder_triangles", "method"});
      UnpricedFrames u;
      const JsonValue max = t.at("max_occluder_triangles");
      const long long count = max.integer();
      if (count < 0) max.fail("must not be negative");
      u.max_occluder_triangles = static_cast<std::size_t>(count);
      if (!p.unpriced_frames.empty() && !(u.max_occluder_triangles > p.unpriced_frames.back().max_occluder_triangles))
        max.fail("must be above the tier before's (" + std::to_string(p.unpriced_frames.back().max_occluder_triangles) +
                 "): the tiers ascend");
      const JsonValue method = t.at("method");
      const std::string name = method.string();
      if (name == "zfail")
        u.method = {gl::ShadowMethod::ZFail, gl::LightProjection::Paper, p.zpass_far};
      else if (name == "zpplus-clipped-sides")
        u.method = {gl::ShadowMethod::ZPPlus, gl::LightProjection::ClippedSides, p.zpass_far};
      else
        method.fail("'" + name + "' is not zfail or zpplus-clipped-sides");
      p.unpriced_frames.push_back(u);
    }
  }
  const JsonValue provenance = j.at("provenance");
  if (!provenance.is_object()) provenance.fail("expected a JSON object, found " + std::string(provenance.type_name()));
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
  if (!p.unpriced_frames.empty()) {
    Json tiers = Json::array();
    for (const UnpricedFrames& u : p.unpriced_frames)
      tiers.push_back({{"max_occluder_triangles", u.max_occluder_triangles}, {"method", u.method.name()}});
    j["unpriced_frames"] = tiers;
  }
  j["provenance"] = Json::parse(p.provenance_json);
  // The provenance names files: a name that is not UTF-8 gets U+FFFD.
  std::string text = j.dump(1, ' ', false, Json::error_handler_t::replace) + "\n";
  parse_policy(text, "the policy to write");  // reads back (device_profile_to_json)
  return text;
}

}  // namespace nearcap::analysis
