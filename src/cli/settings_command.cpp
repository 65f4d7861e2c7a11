// nearcap settings: the settings tables (named_values.hpp) as one JSON
// document, for tools that read nearcap's files: the report script takes its
// method names, order, descriptions and roles from it (nearcap report writes
// it beside the script's other inputs), so that a method added to or renamed
// in a table reaches the report without editing Python.  The format is
// documented in docs/sweeps-and-report.md ("The settings table").
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <string_view>
#include <vector>

#include "cli_commands.hpp"
#include "nearcap/analysis/engine_policies.hpp"
#include "nearcap/analysis/hard_case_sampler.hpp"
#include "nearcap/error.hpp"
#include "nearcap/gl/shadow_methods.hpp"
#include "subcommand.hpp"

namespace nearcap::cli {
namespace {

// The parts the report gives a shadow method, by what the method is, not by
// its name:
//   timing-baseline   the plain Z-pass: the sweep times its frame twice (the
//                     noise floor, analysis/sweep.cpp), the report shows the
//                     other times relative to it, and it is the switch
//                     policy's cost target where Z-pass is right;
//   zfail-baseline    the plain Z-fail, what ZP+ falls back to: the case-D
//                     claim counts only the cracks ZP+ has beyond it;
//   published-zpplus  ZP+ as published (section 3);
//   corrected-zpplus  ZP+ with section 5's corrections: the case-D claim's
//                     subject and the policy's cost target elsewhere.
struct MethodRole {
  gl::ShadowMethod method;
  std::string_view role;
};
constexpr MethodRole kMethodRoles[] = {
    {gl::ShadowMethod::ZPass, "timing-baseline"},
    {gl::ShadowMethod::ZFail, "zfail-baseline"},
    {gl::ShadowMethod::ZPPlus, "published-zpplus"},
    {gl::ShadowMethod::ZPPlusCorrected, "corrected-zpplus"},
};

nlohmann::json roles_of(gl::ShadowMethod m) {
  nlohmann::json roles = nlohmann::json::array();
  for (const MethodRole& r : kMethodRoles)
    if (r.method == m) roles.push_back(std::string(r.role));
  return roles;
}

nlohmann::json method_entry(std::string_view name, std::string_view label, const char* kind, nlohmann::json roles) {
  return {{"name", std::string(name)}, {"label", std::string(label)}, {"kind", kind}, {"roles", std::move(roles)}};
}

template <class E>
nlohmann::json values_json() {
  nlohmann::json values = nlohmann::json::array();
  for (const NamedValue<E>& v : table_of<E>())
    values.push_back({{"name", std::string(v.name)}, {"help", std::string(v.help)}});
  return values;
}

void run() { std::cout << json_text(settings_table_json(), 1) << "\n"; }

struct SettingsOptions {};

}  // namespace

nlohmann::json settings_table_json() {
  // The values of a sweep row's `method` column, in the report's order: the
  // shadow methods, the switch policy, then the engine rules.
  nlohmann::json methods = nlohmann::json::array();
  for (const NamedValue<gl::ShadowMethod>& m : gl::kShadowMethodTable)
    methods.push_back(method_entry(m.name, m.help, "shadow-method", roles_of(m.value)));
  methods.push_back(method_entry("policy", "the switch policy (nearcap tune): a method per occluder", "switch-policy",
                                 nlohmann::json::array({"switch-policy"})));
  for (const NamedValue<analysis::EnginePolicy>& p : analysis::kEnginePolicyTable)
    methods.push_back(method_entry(p.name, p.help, "engine-rule", nlohmann::json::array()));
  return {{"format", "nearcap-settings"},
          {"version", kSettingsTableVersion},
          {"methods", std::move(methods)},
          {"kinds", values_json<analysis::HardCaseKind>()},
          {"choices", emulation_choices_json()}};
}

std::string temporary_file(const std::string& prefix, const std::string& suffix) {
  std::error_code ec;
  std::filesystem::path dir = std::filesystem::temp_directory_path(ec);
  if (ec) dir = "/tmp";
  std::string name = (dir / (prefix + "XXXXXX" + suffix)).string();
  const int fd = ::mkstemps(name.data(), static_cast<int>(suffix.size()));
  if (fd < 0) return "";
  ::close(fd);
  return name;
}

SettingsFile::SettingsFile() : path_(temporary_file("nearcap-settings-", ".json")) {
  if (path_.empty())
    throw Error(ErrorKind::Io, "cannot write the settings table for a script in the temporary directory: " +
                                   std::string(std::strerror(errno)));
  std::ofstream out(path_, std::ios::binary);
  out << json_text(settings_table_json(), 1) << "\n";
  out.close();
  if (!out) {
    std::error_code ec;
    std::filesystem::remove(path_, ec);
    throw Error(ErrorKind::Io, path_ + ": cannot write the settings table for a script");
  }
}

SettingsFile::~SettingsFile() {
  std::error_code ec;
  std::filesystem::remove(path_, ec);
}

void register_settings(CLI::App& app) {
  add_subcommand<SettingsOptions>(
      app, "settings",
      "print the settings tables as JSON: the sweep's methods and rules (name, description, kind, the report's "
      "roles), the sampler's kinds and the emulation choices (docs/sweeps-and-report.md, \"The settings table\")",
      [](const SettingsOptions&) { run(); });
}

}  // namespace nearcap::cli
