// The real-GL commands' frames (see frame_source.hpp).
#include "frame_source.hpp"

#include <chrono>

#include "cli_commands.hpp"
#include "nearcap/error.hpp"

namespace nearcap::cli {

RenderMethods render_methods(const std::string& method, const std::string& policy_file, bool policy_given,
                             const std::string& command) {
  const MethodChoice choice = method_choice(method, false);
  refuse_unread_policy(policy_given, choice.policy, "--method policy (or all)");
  if (choice.raytrace && method != "all")
    throw Error(ErrorKind::Usage, "--method raytrace: nearcap " + command +
                                      " draws the stencil methods and the policy (the ray tracer has no stencil; "
                                      "nearcap cracks runs it)");
  RenderMethods r;
  r.methods = choice.methods;
  if (choice.policy) {
    r.policy = analysis::load_policy(policy_file);
    r.facings = std::make_shared<analysis::FacingCache>();
    r.kept = std::make_shared<analysis::KeptChoices>();
  }
  return r;
}

std::string policy_profile_note(const RenderMethods& methods, const std::string& current_renderer) {
  if (!methods.policy || !methods.policy->device_profile) return "";
  const analysis::DeviceProfile& p = *methods.policy->device_profile;
  const std::string measured_on = p.gl_renderer.empty() ? "no GL named" : "\"" + p.gl_renderer + "\"";
  std::string note = "policy: device profile (" + (p.origin.empty() ? std::string("origin not given") : p.origin) +
                     ") measured on " + measured_on + "\n";
  if (p.gl_renderer != current_renderer)
    note += "policy: this GL is \"" + current_renderer + "\", not the profile's; its costs are used as they are\n";
  return note;
}

FrameSource::FrameSource(const Scene& scene, std::size_t light, const RenderMethods& methods,
                         const gl::EmulationSettings& settings)
    : scene_(scene), light_(light), methods_(methods), settings_(settings), batch_(scene, light, settings) {}

gl::DepthFormat FrameSource::depth(std::size_t k) const {
  if (k < methods_.methods.size() || !methods_.policy->depth) return settings_.depth;
  return *methods_.policy->depth;
}

gl::ShadowFrame FrameSource::frame(std::size_t k) {
  if (k < methods_.methods.size()) return batch_.render(methods_.methods[k]);
  const auto t0 = std::chrono::steady_clock::now();
  if (!cs_) cs_ = std::make_unique<CameraSpaceScene>(scene_);
  decision_ = analysis::decide(*methods_.policy, *cs_, light_, settings_, methods_.facings.get(),
                               analysis::DecisionPricing::ChoiceOnly, methods_.kept.get());
  decision_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  // The predicted frame time and the reasons' prices: what the records
  // report, not part of the frame's work.
  if (methods_.priced)
    analysis::price_decision(decision_, *methods_.policy, *cs_, light_, settings_, methods_.facings.get());
  decision_.settings.record_draws = settings_.record_draws;
  gl::ShadowFrameBatch batch(scene_, light_, decision_.settings);
  return batch.render(decision_.object_methods);
}

}  // namespace nearcap::cli
