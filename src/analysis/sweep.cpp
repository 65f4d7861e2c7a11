// One configuration of a sweep (see sweep.hpp).
#include "nearcap/analysis/sweep.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <sstream>

#include "csv_field.hpp"
#include "nearcap/error.hpp"
#include "nearcap/exact/classification.hpp"
#include "nearcap/exact/eye_setup.hpp"
#include "nearcap/exact/pixel_reference.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/io/utf8_text.hpp"
#include "nearcap/judge/case_comparison.hpp"
#include "nearcap/judge/crack_distances.hpp"
#include "nearcap/judge/crack_map.hpp"

namespace nearcap::analysis {
namespace {

PassWork work(const gl::DrawCounters& c, double ms) { return {c.triangles, c.fragments, c.depth_passed, ms}; }

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4f", v);
  return buf;
}

// A feature: 6 significant digits, "nan" / "inf" as Python and spreadsheets read them.
std::string scientific(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

// "lt_1/512" -> "lt_1_512": column names without a slash.
std::string distance_column(std::string_view name) {
  std::string out(name);
  std::replace(out.begin(), out.end(), '/', '_');
  return out;
}

constexpr const char* kCaseNames[] = {"A", "B", "C1", "C2", "D", "degenerate"};

}  // namespace

std::vector<SweepRow> sweep_configuration(const SweepConfiguration& configuration, const SweepOptions& options) {
  if (configuration.scene_error) throw *configuration.scene_error;
  const Scene scene = parse_scene(configuration.scene_json, configuration.id, ".", options.meshes);
  const CameraSpaceScene cs(scene);
  const SceneClassification exact = classify_scene(cs);
  const CaseComparison engine = compare_engine_cases(cs, exact);
  std::vector<SweepRow> rows;
  EyeSetupCache eye_setups(1);  // the lights of this configuration share the eye side
  for (std::size_t light = 0; light < scene.lights.size(); ++light) {
    const auto t0 = std::chrono::steady_clock::now();
    const PixelReferenceTracer tracer(cs, light, options.light_setups, &eye_setups);
    const PixelReference ref = compute_pixel_reference(tracer);
    const double reference_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    CrackDistances distances(tracer, ref);
    std::array<std::size_t, kQuadCaseCount> exact_cases{};
    for (const ObjectClassification& o : exact.lights[light].objects)
      for (std::size_t c = 0; c < kQuadCaseCount; ++c) exact_cases[c] += o.case_counts[c];
    for (const SweepVariant& variant : options.variants) {
      gl::ShadowFrameBatch batch(scene, light, variant.settings);
      const ConditioningFeatures features =
          conditioning_features(cs, light, batch.light_frustum(), variant.settings.arithmetic);
      // Which occluders Z-pass gets wrong, from the exact near-cap.
      std::vector<bool> zpass_wrong(scene.objects.size(), false);
      std::size_t occluders = 0, wrong_occluders = 0;
      for (std::size_t o = 0; o < scene.objects.size(); ++o) {
        if (!scene.objects[o].occluder) continue;
        ++occluders;
        zpass_wrong[o] = ref.cap_pixels_by_object[o] > 0;
        if (zpass_wrong[o]) ++wrong_occluders;
      }
      // A row per method, then one per engine policy (a frame with a method per occluder).
      struct Entry {
        std::string name;
        std::optional<gl::ShadowMethod> method;
        std::vector<gl::ShadowMethod> object_methods;
        double decide_ms = 0;
        gl::ShadowFrameBatch* batch = nullptr;  // the frame's settings, when not the variant's
      };
      std::vector<Entry> entries;
      for (gl::ShadowMethod m : options.methods) entries.push_back({std::string(to_string(m)), m, {}});
      for (EnginePolicy p : options.policies)
        entries.push_back(
            {std::string(to_string(p)), std::nullopt, object_methods(scene, engine_choices(p, scene, light))});
      // The switch policy: its decision, and a batch with its settings (its switch clamp).
      std::unique_ptr<gl::ShadowFrameBatch> policy_batch;
      gl::EmulationSettings policy_settings;
      if (options.switch_policy) {
        // Its choice (decide_ms): a row reads no price.
        const PolicyDecision d =
            decide(*options.switch_policy, cs, light, variant.settings, nullptr, DecisionPricing::ChoiceOnly);
        policy_settings = d.settings;
        policy_batch = std::make_unique<gl::ShadowFrameBatch>(scene, light, d.settings);
        entries.push_back({"policy", std::nullopt, d.object_methods, d.decide_ms, policy_batch.get()});
      }
      std::optional<std::size_t> zpass_row;  // this light and variant's Z-pass row, when drawn
      for (const Entry& entry : entries) {
        SweepRow r;
        r.variant = variant.name;
        r.configuration = configuration.id;
        r.source = configuration.source;
        r.kind = configuration.kind;
        r.detail = configuration.detail;
        r.replay = configuration.replay;
        r.light = light;
        r.method = entry.name;
        r.occluders = occluders;
        r.zpass_wrong_occluders = wrong_occluders;
        // The method each occluder gets, where the row draws each occluder with
        // Z-pass or a method right where Z-pass is wrong (Z-fail, preload): the
        // engine rules, the policy, and those methods themselves.
        std::vector<gl::ShadowMethod> decided = entry.object_methods;
        if (entry.method && (*entry.method == gl::ShadowMethod::ZPass || *entry.method == gl::ShadowMethod::ZFail ||
                             *entry.method == gl::ShadowMethod::Preload))
          decided.assign(scene.objects.size(), *entry.method);
        if (!decided.empty()) {
          r.false_negatives = r.false_positives = 0;
          for (std::size_t o = 0; o < scene.objects.size(); ++o) {
            if (!scene.objects[o].occluder) continue;
            const bool zpass = decided[o] == gl::ShadowMethod::ZPass;
            if (zpass && zpass_wrong[o]) ++r.false_negatives;
            if (!zpass && !zpass_wrong[o]) ++r.false_positives;
          }
        }
        r.exact_cases = exact_cases;
        r.case_disagreements = engine.total(light);
        r.reference_ms = reference_ms;
        r.reference_setup_ms = ref.setup_ms;
        r.reference_trace_ms = ref.trace_ms;
        r.decide_ms = entry.decide_ms;
        r.features = features;
        gl::ShadowFrame frame;
        try {
          gl::ShadowFrameBatch& b = entry.batch ? *entry.batch : batch;
          frame = entry.method ? b.render(*entry.method) : b.render(entry.object_methods);
        } catch (const Error& e) {
          if (e.kind() != ErrorKind::Range) throw;
          r.refused = true;  // a GL would draw NaN vertices; the emulation refuses (gl/pipeline.hpp)
          r.fallback = std::string("refused: ") + e.what();
          rows.push_back(std::move(r));
          continue;
        }
        CrackReport report = judge_frame(frame, ref);
        const double measured_before = distances.ms();
        distances.measure(report);
        r.float_cases = frame.float_cases;
        r.pixels_seen = report.pixels_seen;
        r.wrong = report.wrong;
        r.wrong_lit = report.wrong_lit;
        r.wrong_shadowed = report.wrong_shadowed;
        r.count_mismatch = report.count_mismatch;
        r.cracks = *report.cracks;
        r.wrong_by_distance = *report.wrong_by_distance;
        r.crack_distance_ms = distances.ms() - measured_before;
        r.cap_mismatch = report.cap_mismatch ? static_cast<long long>(*report.cap_mismatch) : -1;
        r.visibility_mismatch = report.visibility_mismatch;
        const gl::EmulationSettings& drawn = entry.batch ? policy_settings : variant.settings;
        r.depth_limited = depth_step_over_size(cs, frame.near, drawn.depth, drawn.depth_mapping) >= kDepthLimitedStep;
        r.fallback = frame.fallback;
        r.zfail_objects = frame.zfail_objects.size();
        r.setup = {0, 0, 0, frame.times.setup_ms};
        r.depth = work(frame.depth_pass, frame.times.depth_ms);
        r.near_cap = work(frame.cap_pass, frame.times.cap_ms);
        r.volume = work(frame.volume_pass, frame.times.volume_ms);
        if (entry.method == gl::ShadowMethod::ZPass) zpass_row = rows.size();
        rows.push_back(std::move(r));
      }
      // The noise floor: Z-pass's frame again, after the other methods, in a
      // batch of its own, so that nothing the first timing measured (the tight
      // near plane, silhouettes, the depth pre-pass) is reused, only timed anew.
      if (zpass_row) {
        gl::ShadowFrameBatch again(scene, light, variant.settings);
        rows[*zpass_row].frame_again_ms = again.render(gl::ShadowMethod::ZPass).times.total();
      }
    }
  }
  return rows;
}

std::string csv_header() {
  std::string h = "configuration,source,kind,detail,light,method,variant";
  for (const char* c : kCaseNames) h += std::string(",exact_") + c;
  for (const char* c : kCaseNames)
    if (std::string(c) != "degenerate") h += std::string(",float_") + c;
  h += ",case_disagreements,pixels_seen,wrong,cracks,wrong_lit,wrong_shadowed,count_mismatch,cap_mismatch,"
       "visibility_mismatch,fallback,zfail_objects,refused,occluders,zpass_wrong_occluders,false_negatives,"
       "false_positives";
  for (std::string_view name : kCrackDistanceNames) h += ",wrong_r_" + distance_column(name);
  h += ",light_frustum_defined,light_near_distance,l_far_over_width,delta_over_width,skew,l_near_over_l_far,"
       "cond_projection,cond_light_transform,coordinate_over_size,depth_step_over_size,cap_window_error_px,"
       "cap_window_error_ulp,"
       "cap_vertices,depth_limited";
  for (const char* pass : {"depth", "near_cap", "volume"})
    h += std::string(",") + pass + "_triangles," + pass + "_fragments," + pass + "_depth_pass," + pass +
         "_depth_fail," + pass + "_ms";
  h += ",setup_ms,frame_ms,frame_again_ms,decide_ms,reference_ms,crack_distance_ms,replay,reference_setup_ms,reference_"
       "trace_ms\n";
  return h;
}

// A text field of a row: its control characters written as escapes (an
// error message in `fallback` can name a file whose name holds a line feed),
// so that no field holds a line break, then quoted where CSV needs it.
namespace {
std::string text_field(const std::string& text) { return csv_field(io::escaped_control_characters(text)); }
}  // namespace

std::string csv_line(const SweepRow& r) {
  std::ostringstream s;
  s << text_field(r.configuration) << ',' << text_field(r.source) << ',' << text_field(r.kind) << ','
    << text_field(r.detail) << ',' << r.light << ',' << r.method << ',' << text_field(r.variant);
  for (std::size_t c = 0; c < kQuadCaseCount; ++c) s << ',' << r.exact_cases[c];
  for (std::size_t c = 0; c + 1 < kQuadCaseCount; ++c) s << ',' << r.float_cases[c];
  s << ',' << r.case_disagreements << ',' << r.pixels_seen << ',' << r.wrong << ',' << r.cracks << ',' << r.wrong_lit
    << ',' << r.wrong_shadowed << ',' << r.count_mismatch << ',';
  if (r.cap_mismatch >= 0) s << r.cap_mismatch;
  s << ',' << r.visibility_mismatch << ',' << text_field(r.fallback) << ',' << r.zfail_objects << ','
    << (r.refused ? 1 : 0) << ',' << r.occluders << ',' << r.zpass_wrong_occluders << ',';
  if (r.false_negatives >= 0) s << r.false_negatives;
  s << ',';
  if (r.false_positives >= 0) s << r.false_positives;
  for (std::size_t n : r.wrong_by_distance) s << ',' << n;
  const ConditioningFeatures& f = r.features;
  s << ',' << (f.light_frustum_defined ? 1 : 0);
  for (double v : {f.light_near_distance, f.l_far_over_width, f.delta_over_width, f.skew, f.l_near_over_l_far,
                   f.cond_projection, f.cond_light_transform, f.coordinate_over_size, f.depth_step_over_size,
                   f.cap_window_error_px, f.cap_window_error_ulp})
    s << ',' << scientific(v);
  s << ',' << f.cap_vertices << ',' << (r.depth_limited ? 1 : 0);
  for (const PassWork* p : {&r.depth, &r.near_cap, &r.volume})
    s << ',' << p->triangles << ',' << p->fragments << ',' << p->depth_passed << ',' << p->fragments - p->depth_passed
      << ',' << number(p->ms);
  const double frame_ms = r.setup.ms + r.depth.ms + r.near_cap.ms + r.volume.ms;
  s << ',' << number(r.setup.ms) << ',' << number(frame_ms) << ',';
  if (r.frame_again_ms) s << number(*r.frame_again_ms);
  s << ',' << number(r.decide_ms) << ',' << number(r.reference_ms) << ',' << number(r.crack_distance_ms) << ','
    << text_field(r.replay) << ',' << number(r.reference_setup_ms) << ',' << number(r.reference_trace_ms) << '\n';
  return s.str();
}

}  // namespace nearcap::analysis
