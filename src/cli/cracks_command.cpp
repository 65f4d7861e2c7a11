// nearcap cracks SCENE --light K [--method M|all] [...]: the float pipeline's
// methods against the exact reference, one JSON record per method.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>

#include "cli_commands.hpp"
#include "command_output.hpp"
#include "method_records.hpp"
#include "nearcap/analysis/switch_policy.hpp"
#include "nearcap/error.hpp"
#include "nearcap/exact/classification.hpp"
#include "nearcap/exact/eye_count.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/judge/case_comparison.hpp"
#include "nearcap/judge/crack_distances.hpp"
#include "nearcap/judge/crack_map.hpp"
#include "nearcap/raytrace/shadow_ray_tracer.hpp"
#include "subcommand.hpp"

namespace nearcap::cli {
namespace {

struct CracksOptions {
  std::string scene;
  std::size_t light = 0;
  std::string method = "all";
  std::string policy = shipped_data_dir() + "/policy.json";
  bool policy_given = false;  // --policy on the command line
  raytrace::ShadowEpsilon shadow_epsilon = raytrace::ShadowEpsilon::Fixed;
  bool shadow_epsilon_given = false;  // --shadow-epsilon on the command line
  EmulationOptions emulation;
  std::string out;
  bool table = false;
  double max_memory_gb = 0;
};

// Memory per pixel beyond the fixed 64 MB: the exact reference, one emulated
// frame at a time (depth, stencil, object ids, near-cap copy), and one
// encoded crack image per method.  The peaks measured at 2048x2048
// (docs/findings/exact-speed.md, "Memory") are 31 bytes per pixel beyond 64
// MB with one method, 43 with two (the second projection's depth pre-pass)
// and 51 with `all` (the policy's own batch; raytrace's frame is freed by
// then), against estimates of 32, 43 and 64.
constexpr double kCracksBytesPerPixel = 30;
constexpr double kCracksBytesPerPixelPerMethod = 2;
constexpr double kCracksBytesPerPixelPerBatch = 9;  // a second depth pre-pass; the policy's batch

// What every judged record holds: the method, its wrong pixels and their
// crack distances, the count and visibility mismatches.
nlohmann::json judged_json(const CrackReport& r) {
  nlohmann::json j;
  j["method"] = r.method;
  j["pixels_seen"] = r.pixels_seen;
  j["wrong"] = r.wrong;
  j["wrong_lit"] = r.wrong_lit;
  j["wrong_shadowed"] = r.wrong_shadowed;
  if (r.cracks) {
    j["cracks"] = *r.cracks;
    nlohmann::json buckets = nlohmann::json::object();
    for (std::size_t k = 0; k < kCrackDistanceLevels; ++k)
      buckets[std::string(kCrackDistanceNames[k])] = (*r.wrong_by_distance)[k];
    j["wrong_by_distance"] = buckets;
  }
  j["count_mismatch"] = r.count_mismatch;
  j["visibility_mismatch"] = r.visibility_mismatch;
  return j;
}

// `eye`: the exact eye count, for a frame with AtomicZP's float one.
nlohmann::json record_json(const gl::ShadowFrame& f, const CrackReport& r, std::size_t case_disagreements,
                           const std::optional<ExactEyeCount>& eye = std::nullopt) {
  nlohmann::json j = judged_json(r);
  if (f.eye_count && eye)
    j["eye_count"] = {{"float", *f.eye_count},
                      {"exact", eye->count},
                      {"on_boundary", eye->on_boundary},
                      {"triangles", f.eye_count_triangles}};
  j["cap_mismatch"] = r.cap_mismatch ? nlohmann::json(*r.cap_mismatch) : nlohmann::json(nullptr);
  j["case_disagreements"] = case_disagreements;
  j["ms"] = f.times.total();
  j["pass_ms"] = {{"setup", f.times.setup_ms},
                  {"depth", f.times.depth_ms},
                  {"near_cap", f.times.cap_ms},
                  {"volume", f.times.volume_ms}};
  j["fragments"] = {
      {"depth", f.depth_pass.fragments}, {"near_cap", f.cap_pass.fragments}, {"volume", f.volume_pass.fragments}};
  nlohmann::json cases = nlohmann::json::object();
  for (std::size_t c = 0; c + 1 < kQuadCaseCount; ++c)
    cases[std::string(to_string(static_cast<QuadCase>(c)))] = f.float_cases[c];
  j["float_cases"] = cases;
  j["zfail_objects"] = f.zfail_objects;
  j["fallback"] = f.fallback.empty() ? nlohmann::json(nullptr) : nlohmann::json("zfail: " + f.fallback);
  if (gl::uses_near_cap(f.method) && f.light_frustum.defined)
    j["light_frustum"] = {{"alpha", f.light_frustum.alpha},
                          {"l_near", f.light_frustum.l_near},
                          {"l_far", f.light_frustum.l_far},
                          {"d", f.light_frustum.d},
                          {"d_max", f.light_frustum.d_max}};
  return j;
}

// --table: a row per method, the raytrace and policy lines, and the float
// engine's cases with their legend.
void print_table(const std::vector<nlohmann::json>& records, const PixelReference& ref, std::size_t light) {
  std::printf("%-17s %9s %7s %7s %9s %9s %8s %8s %7s %9s %9s\n", "method", "seen", "wrong", "cracks", "wrong-lit",
              "wrong-shd", "count!=", "cap!=", "cases!=", "visib!=", "ms");
  for (const nlohmann::json& r : records) {
    if (r.contains("refused")) {
      print_refused_row(r);
      continue;
    }
    const std::string cap = r["cap_mismatch"].is_null() ? "-" : std::to_string(r["cap_mismatch"].get<std::size_t>());
    const std::string cases =
        r["case_disagreements"].is_null() ? "-" : std::to_string(r["case_disagreements"].get<std::size_t>());
    std::printf("%-17s %9zu %7zu %7zu %9zu %9zu %8zu %8s %7s %9zu %9.1f%s\n", r["method"].get<std::string>().c_str(),
                r["pixels_seen"].get<std::size_t>(), r["wrong"].get<std::size_t>(), r["cracks"].get<std::size_t>(),
                r["wrong_lit"].get<std::size_t>(), r["wrong_shadowed"].get<std::size_t>(),
                r["count_mismatch"].get<std::size_t>(), cap.c_str(), cases.c_str(),
                r["visibility_mismatch"].get<std::size_t>(), r["ms"].get<double>(),
                r["fallback"].is_null() ? "" : "  (fell back to zfail)");
  }
  for (const nlohmann::json& r : records)
    if (r.contains("shadow_epsilon"))
      std::printf(
          "raytrace: Embree float32, shadow epsilon %s, BVH %.1f ms, rays %.1f ms; exact reference: setup %.1f ms, "
          "trace %.1f ms\n",
          r["shadow_epsilon"].get<std::string>().c_str(), r["pass_ms"]["build"].get<double>(),
          r["pass_ms"]["trace"].get<double>(), ref.setup_ms, ref.trace_ms);
  for (const nlohmann::json& r : records)
    if (r.contains("occluders")) {
      std::printf("policy (decided in %.3f ms):", r["decide_ms"].get<double>());
      print_occluder_lines(r["occluders"]);
    }
  const auto drawn =
      std::find_if(records.begin(), records.end(), [](const nlohmann::json& r) { return r.contains("float_cases"); });
  if (drawn != records.end()) {  // a stencil method ran (not raytrace alone)
    const nlohmann::json& cases = (*drawn)["float_cases"];
    std::printf("float engine's cases for light %zu:", light);
    for (const char* c : {"A", "B", "C1", "C2", "D"}) std::printf(" %s %zu", c, cases[c].get<std::size_t>());
    std::printf("\n");
    std::fflush(stdout);
    print_case_legend(std::cout);
  }
}

// The policy's name in its crack image's legend: "policy" and the methods it
// ran on the occluders, e.g. "policy (zpplus-corrected on 2 occluders, zfail on 1)".
std::string policy_label(const Scene& scene, const analysis::PolicyDecision& d) {
  std::string ran;
  bool first = true;
  for (gl::ShadowMethod m : gl::kAllShadowMethods) {
    std::size_t n = 0;
    for (std::size_t o = 0; o < scene.objects.size(); ++o)
      if (scene.objects[o].occluder && d.object_methods[o] == m) ++n;
    if (n == 0) continue;
    ran += (ran.empty() ? "" : ", ") + std::string(to_string(m)) + " on " + std::to_string(n) +
           (first ? (n == 1 ? " occluder" : " occluders") : "");
    first = false;
  }
  return ran.empty() ? "policy (no occluders)" : "policy (" + ran + ")";
}

// A ray-traced frame's record: the judged counts, its times and its choice.
nlohmann::json raytrace_json(const raytrace::RaytraceFrame& f, const CrackReport& r, double build_ms,
                             raytrace::ShadowEpsilon epsilon) {
  nlohmann::json j = judged_json(r);
  j["cap_mismatch"] = nullptr;
  j["case_disagreements"] = nullptr;  // the float engine's cases: not the ray tracer's
  j["ms"] = build_ms + f.trace_ms;
  j["pass_ms"] = {{"build", build_ms}, {"trace", f.trace_ms}};
  j["shadow_epsilon"] = std::string(to_string(epsilon));
  j["fallback"] = nullptr;
  return j;
}

void run(const CracksOptions& o) {
  const MethodChoice choice = method_choice(o.method);
  const std::vector<gl::ShadowMethod>& methods = choice.methods;
  refuse_non_directory(o.out, "--out");
  std::optional<analysis::SwitchPolicy> policy;
  refuse_unread_policy(o.policy_given, choice.policy, "--method policy (or all)");
  if (o.shadow_epsilon_given && !choice.raytrace)
    throw Error(ErrorKind::Usage,
                "--shadow-epsilon is read only with --method raytrace (or all): no method chosen "
                "traces shadow rays");
  if (choice.policy) policy = analysis::load_policy(o.policy);
  const gl::EmulationSettings settings = settings_from(o.emulation);
  const Scene scene = load_scene(o.scene);
  check_light_index(scene, o.light);
  check_memory_estimate(scene, "cracks",
                        kCracksBytesPerPixel + kCracksBytesPerPixelPerMethod * static_cast<double>(choice.count()) +
                            kCracksBytesPerPixelPerBatch * ((methods.size() > 1 ? 1 : 0) + (choice.policy ? 1 : 0)),
                        o.max_memory_gb);
  const CameraSpaceScene cs(scene);
  const PixelReferenceTracer tracer(cs, o.light);
  const PixelReference ref = compute_pixel_reference(tracer);
  CrackDistances distances(tracer, ref);
  const SceneClassification classification = classify_scene(cs);
  const std::size_t case_disagreements = compare_engine_cases(cs, classification).total(o.light);

  MethodRecords records(choice.count());
  std::vector<CommandInput> inputs = scene_inputs(scene);
  if (choice.policy) inputs.push_back({o.policy, "policy file"});
  OutputDir out(o.out, std::move(inputs));
  // A method's crack image: cracks.png when it runs alone.
  const auto image_name = [&](const std::string& method) {
    return choice.count() == 1 ? std::string("cracks.png") : "cracks-" + method + ".png";
  };
  gl::ShadowFrameBatch batch(scene, o.light, settings);
  std::optional<ExactEyeCount> exact_eye;  // computed for the first AtomicZP frame
  for (gl::ShadowMethod m : methods) {
    const std::string name(to_string(m));
    gl::ShadowFrame frame;
    try {
      frame = batch.render(m);
    } catch (const Error& e) {
      // Float32 transforms too degenerate to draw (a clipped vertex at
      // (0, 0, 0, 0)): this method refuses the frame, the others still run.
      if (records.refuse(name, e, {ErrorKind::Range}) == choice.count()) throw;  // no method can draw this frame
      continue;
    }
    CrackReport report = judge_frame(frame, ref);
    distances.measure(report);
    if (frame.eye_count && !exact_eye) exact_eye = exact_eye_count(cs, o.light);
    records.add(record_json(frame, report, case_disagreements, exact_eye));
    out.add(image_name(name), [&] { return crack_png(cs, ref, report); });
  }
  if (policy) {
    // The policy decides per occluder, then its frame is drawn with the
    // settings it needs (its switch clamp).
    const analysis::PolicyDecision d = analysis::decide(*policy, cs, o.light, settings);
    gl::ShadowFrameBatch policy_batch(scene, o.light, d.settings);
    gl::ShadowFrame frame;
    try {
      frame = policy_batch.render(d.object_methods);
    } catch (const Error& e) {
      if (records.refuse("policy", e, {ErrorKind::Range}) == choice.count()) throw;
      frame.width = 0;
    }
    if (frame.width > 0) {
      CrackReport report = judge_frame(frame, ref);
      distances.measure(report);
      nlohmann::json r = record_json(frame, report, case_disagreements);
      r.update(policy_decision_json(scene, d));
      r["method"] = "policy";
      r["decide_ms"] = d.decide_ms;
      r["crack_probability"] =
          std::isfinite(d.crack_probability) ? nlohmann::json(d.crack_probability) : nlohmann::json(nullptr);
      records.add(r);
      report.method = policy_label(scene, d);
      out.add(image_name("policy"), [&] { return crack_png(cs, ref, report); });
    }
  }
  if (choice.raytrace) {
    // Embree, float32: its BVHs built here, its frame judged by status.
    try {
      const raytrace::EmbreeScene embree(scene);
      raytrace::RaytraceSettings rs;
      rs.epsilon = o.shadow_epsilon;
      const raytrace::RaytraceFrame frame = embree.trace(o.light, rs);
      CrackReport report = judge_raytrace_frame(frame, ref);
      distances.measure(report);
      nlohmann::json r = raytrace_json(frame, report, embree.build_ms(), o.shadow_epsilon);
      // The exact side beside Embree's: its setup (light and eye sides, like
      // the BVHs) and its tracing.
      r["reference_ms"] = {{"setup", ref.setup_ms}, {"trace", ref.trace_ms}};
      records.add(r);
      out.add(image_name("raytrace"), [&] { return crack_png(cs, ref, report); });
    } catch (const Error& e) {
      // Built without Embree, or rays beyond float32: `all` still runs the
      // rest and says why not.
      if (records.refuse("raytrace", e, {ErrorKind::Unavailable, ErrorKind::Range}) == choice.count()) throw;
    }
  }
  const nlohmann::json root =
      choice.count() == 1 ? records.records().front() : nlohmann::json{{"methods", records.records()}};
  nlohmann::json file = root;
  file["scene"] = scene.source;
  file["light"] = o.light;
  file["reference_ms"] = ref.setup_ms + ref.trace_ms;
  file["reference_setup_ms"] = ref.setup_ms;
  file["reference_trace_ms"] = ref.trace_ms;
  file["crack_distance_ms"] = distances.ms();
  out.write("cracks.json", file);
  if (o.table)
    print_table(records.records(), ref, o.light);
  else
    print_json_line(root);
}

}  // namespace

void register_cracks(CLI::App& app) {
  auto [cmd, o] = add_subcommand<CracksOptions>(
      app, "cracks",
      "emulate the float GL pipeline's shadow methods and count the pixels they get wrong against the exact "
      "reference: one JSON record per method (or a table with --table); with --out DIR, DIR/cracks.png "
      "(cracks-METHOD.png for several methods) and DIR/cracks.json",
      run);
  add_scene_argument(cmd, o.scene)->required();
  add_light_option(cmd, o.light);
  cmd.add_option("--method", o.method,
                 names_joined<gl::ShadowMethod>() +
                     ", raytrace (Embree, float32), policy (a method per occluder, from --policy), comma-separated, "
                     "or all (the six, raytrace and the policy)")
      ->capture_default_str();
  note_given(cmd.add_option("--policy", o.policy, "the switch policy for --method policy (nearcap tune writes one)"),
             o.policy_given)
      ->capture_default_str();
  note_given(add_choice_option(
                 cmd, "--shadow-epsilon", o.shadow_epsilon,
                 "how raytrace's shadow rays leave their surface: " + values_described<raytrace::ShadowEpsilon>(", ")),
             o.shadow_epsilon_given);
  add_emulation_options(cmd, o.emulation);
  cmd.add_option("--out", o.out, "output directory for the crack images and cracks.json (created if missing)");
  cmd.add_flag("--table", o.table, "print a human-readable table instead of JSON");
  add_max_memory_option(cmd, o.max_memory_gb);
}

}  // namespace nearcap::cli
