// The real-GL commands' frames (nearcap render, nearcap view): what --method
// names among the stencil methods and the switch policy, and each light's
// emulated frame per method, with its recorded draws for the real GL.
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "nearcap/analysis/switch_policy.hpp"
#include "nearcap/exact/camera_space.hpp"
#include "nearcap/gl/shadow_methods.hpp"
#include "nearcap/scene/scene.hpp"

namespace nearcap::cli {

// What --method names: stencil methods, and "policy" (the switch policy's
// method per occluder, with the settings it needs); "all" is the five and
// the policy.
struct RenderMethods {
  std::vector<gl::ShadowMethod> methods;
  std::optional<analysis::SwitchPolicy> policy;
  // The occluders' facings the policy's decisions keep across frames (the
  // lights and occluders of a path stay put while its camera moves).
  std::shared_ptr<analysis::FacingCache> facings;
  // The policy's priced choices, kept for the next few decisions of a light
  // while the scene's objects and lights stay put (kept_choices.hpp).
  std::shared_ptr<analysis::KeptChoices> kept;
  // Whether each decision is priced after its choice (the predicted frame
  // time and the reasons the records report): not where nothing reads them.
  bool priced = true;
  std::size_t count() const { return methods.size() + (policy ? 1 : 0); }
  std::string name(std::size_t k) const { return k < methods.size() ? std::string(to_string(methods[k])) : "policy"; }
};

// `command` names the command in the refusal of raytrace (no stencil).
// Throws Error(Usage) for an unknown name, for a --policy given (`policy_given`)
// that no method chosen reads, and what load_policy throws.
RenderMethods render_methods(const std::string& method, const std::string& policy_file, bool policy_given,
                             const std::string& command);

// What --method policy prices its candidates with: "" without the policy or
// its device profile; else a line naming the profile's origin and the
// GL_RENDERER it was measured on, and, when `current_renderer` differs, a
// second line saying so (the profile is still used).
std::string policy_profile_note(const RenderMethods& methods, const std::string& current_renderer);

// The frames of one scene and light, method by method (k indexes
// RenderMethods: the policy last), sharing a batch for the fixed methods.
class FrameSource {
 public:
  FrameSource(const Scene& scene, std::size_t light, const RenderMethods& methods,
              const gl::EmulationSettings& settings);
  gl::ShadowFrame frame(std::size_t k);
  // The depth buffer method k's frames are drawn with: the settings', or the
  // policy's own (a version-3 policy may name one).
  gl::DepthFormat depth(std::size_t k) const;
  // The policy's last decision (after frame(k) of the policy).
  const analysis::PolicyDecision& decision() const { return decision_; }
  // Its CPU time (steady_clock, ms): the camera-space scene the policy reads
  // (the first time), and the decision's choice, its exact Z-pass test
  // included (analysis::DecisionPricing::ChoiceOnly; the prices the records
  // read are computed after).
  double decision_ms() const { return decision_ms_; }

 private:
  const Scene& scene_;
  std::size_t light_;
  const RenderMethods& methods_;
  gl::EmulationSettings settings_;
  gl::ShadowFrameBatch batch_;
  std::unique_ptr<CameraSpaceScene> cs_;
  analysis::PolicyDecision decision_;
  double decision_ms_ = 0;
};

}  // namespace nearcap::cli
