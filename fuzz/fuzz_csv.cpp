// libFuzzer target: the sweep-CSV reader `nearcap tune` fits on
// (analysis/policy_fit.hpp: policy_samples and cost_samples, on text).  Any
// input must be read or rejected with a nearcap::Error; what is read must
// hold what the reader promises: finite features, finite non-negative work
// and times, the documented split.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "nearcap/analysis/policy_fit.hpp"
#include "nearcap/error.hpp"

namespace {

using nearcap::gl::ShadowMethod;

void check_policy_samples(const std::string& text, const char* variant) {
  try {
    for (const nearcap::analysis::PolicySample& s : nearcap::analysis::policy_samples_from_text(
             text, "fuzz.csv", ShadowMethod::ZPPlusCorrected, ShadowMethod::ZFail, variant)) {
      if (s.x.size() != nearcap::analysis::kPolicyFeatures.size()) std::abort();
      for (double v : s.x)
        if (!std::isfinite(v)) std::abort();
      if (s.held_out != nearcap::analysis::held_out_configuration(s.configuration)) std::abort();
    }
  } catch (const nearcap::Error&) {
  }
}

void check_cost_samples(const std::string& text, ShadowMethod method, const char* variant) {
  try {
    for (const nearcap::analysis::CostSample& s :
         nearcap::analysis::cost_samples_from_text(text, "fuzz.csv", method, variant))
      if (!(s.triangles >= 0 && s.fragments >= 0 && s.ms >= 0) || !std::isfinite(s.triangles) ||
          !std::isfinite(s.fragments) || !std::isfinite(s.ms))
        std::abort();
  } catch (const nearcap::Error&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > 64 * 1024) return 0;  // bounded input size
  const std::string text(reinterpret_cast<const char*>(data), size);
  // The sweep's plain variant where the rows have it, else the policy's own
  // (tune's default), so that rows of either kind of sweep reach the number
  // parsing; one cost reader (the two methods' rows parse alike).
  const char* variant = text.find(",default,") != std::string::npos ? "default" : "switch-clamp=clamp-far";
  check_policy_samples(text, variant);
  check_cost_samples(text, ShadowMethod::ZFail, variant);
  return 0;
}
