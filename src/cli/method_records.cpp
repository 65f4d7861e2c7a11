// The per-method records (see method_records.hpp).
#include "method_records.hpp"

#include <algorithm>
#include <cstdio>

#include "cli_commands.hpp"

namespace nearcap::cli {

std::size_t MethodRecords::refuse(const std::string& method, const Error& e,
                                  std::initializer_list<ErrorKind> refusing) {
  if (methods_ == 1 || std::find(refusing.begin(), refusing.end(), e.kind()) == refusing.end()) throw;
  records_.push_back({{"method", method}, {"refused", e.what()}});
  return ++refused_;
}

nlohmann::json policy_decision_json(const Scene& scene, const analysis::PolicyDecision& d) {
  nlohmann::json j{{"occluders", policy_occluders_json(scene, d)}, {"depth_limited", d.depth_limited}};
  if (d.depth_limited) j["depth_note"] = d.depth_note();
  if (const std::string note = d.near_plane_note(); !note.empty()) j["near_plane_note"] = note;
  return j;
}

void print_refused_row(const nlohmann::json& record, const char* indent) {
  std::printf("%s%-17s refused: %s\n", indent, record["method"].get<std::string>().c_str(),
              record["refused"].get<std::string>().c_str());
}

void print_occluder_lines(const nlohmann::json& occluders) {
  for (const nlohmann::json& oc : occluders)
    std::printf("\n  object %zu: %s, %s", oc["object"].get<std::size_t>(), oc["method"].get<std::string>().c_str(),
                oc["why"].get<std::string>().c_str());
  std::printf("\n");
}

}  // namespace nearcap::cli
