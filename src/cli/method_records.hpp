// The per-method records of nearcap cracks and nearcap render --compare: a
// JSON record for each method drawn, one saying why for a method whose frame
// cannot be drawn, the policy's decision in its record, and the lines their
// --table prints for these.
#pragma once

#include <nlohmann/json.hpp>

#include <cstddef>
#include <initializer_list>
#include <string>
#include <vector>

#include "nearcap/analysis/switch_policy.hpp"
#include "nearcap/error.hpp"
#include "nearcap/scene/scene.hpp"

namespace nearcap::cli {

class MethodRecords {
 public:
  // `methods`: how many methods the command runs.
  explicit MethodRecords(std::size_t methods) : methods_(methods) {}

  void add(nlohmann::json record) { records_.push_back(std::move(record)); }

  // Called while `e` is handled (in a catch block), for an Error thrown by
  // drawing `method`'s frame: when e's kind is one of `refusing` and the
  // command runs more than one method, adds {"method", "refused": e.what()}
  // and returns how many methods have been refused so far (the others still
  // run); else rethrows e, the command's own error.
  std::size_t refuse(const std::string& method, const Error& e, std::initializer_list<ErrorKind> refusing);

  const std::vector<nlohmann::json>& records() const { return records_; }

 private:
  std::size_t methods_;
  std::size_t refused_ = 0;
  std::vector<nlohmann::json> records_;
};

// The policy's decision as a record holds it: its method per occluder and
// why ("occluders": [{"object", "method", "why"}]), "depth_limited",
// "depth_note" when it is, and "near_plane_note" when the policy drew the
// frame with the tight near plane to avoid it.
nlohmann::json policy_decision_json(const Scene& scene, const analysis::PolicyDecision& d);

// --table: a refused method's row, `indent` then "METHOD refused: WHY"
// (the method in the table's first column, 17 characters).
void print_refused_row(const nlohmann::json& record, const char* indent = "");

// --table: each occluder's line of a record's "occluders" ("\n  object K:
// METHOD, WHY"), then the end of the line, after the caller's heading.
void print_occluder_lines(const nlohmann::json& occluders);

}  // namespace nearcap::cli
