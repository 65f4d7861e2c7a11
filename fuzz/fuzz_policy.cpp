// libFuzzer target: the switch policy reader (analysis/switch_policy.hpp,
// parse_policy on text).  Any input must be read or rejected with a
// nearcap::Error; a policy read must write out (policy_to_json) to text that
// reads back to the same policy.
#include <cstdint>
#include <cstdlib>
#include <string>

#include "nearcap/analysis/switch_policy.hpp"
#include "nearcap/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > 64 * 1024) return 0;  // bounded input size
  const std::string text(reinterpret_cast<const char*>(data), size);
  nearcap::analysis::SwitchPolicy policy;
  try {
    policy = nearcap::analysis::parse_policy(text, "fuzz.json");
  } catch (const nearcap::Error&) {
    return 0;
  }
  const std::string written = nearcap::analysis::policy_to_json(policy);
  try {
    if (nearcap::analysis::policy_to_json(nearcap::analysis::parse_policy(written, "written.json")) != written)
      std::abort();
  } catch (const nearcap::Error&) {
    std::abort();  // what it wrote it must read
  }
  return 0;
}
