// nearcap/numeric/filter_stats.hpp — how often each exact predicate needed rationals.
//
// Every predicate first evaluates its expression in BoundedDouble; only when
// zero lies inside the certified error bound does it recompute over rationals.
// For a robustness study that fallback count is data (geogram counts it too):
// it says how close a scene sits to a degeneracy.  Counters are plain integers;
// each thread keeps its own FilterStats and merges at the end.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

namespace nearcap {

enum class Predicate : int {
  LightFacing,      // side of a triangle's plane the light lies on
  NearPlaneSide,    // side of the camera's near plane a point (or direction) lies on
  SegmentCrossing,  // does segment [l, p] cross a triangle (near-cap, inside tests)
  RayHit,           // does the view ray through a pixel centre hit a triangle, and where
  ShadowCrossing,   // does segment (l, q) cross a light-front-facing triangle
  Arrangement,      // near-cap arrangement constructions
  kCount
};

std::string_view to_string(Predicate p);

struct FilterStats {
  std::array<std::uint64_t, static_cast<int>(Predicate::kCount)> filtered{};  // decided in BoundedDouble
  std::array<std::uint64_t, static_cast<int>(Predicate::kCount)> exact{};     // needed rationals

  void record(Predicate p, bool needed_exact) { (needed_exact ? exact : filtered)[static_cast<int>(p)] += 1; }
  void merge(const FilterStats& o) {
    for (int i = 0; i < static_cast<int>(Predicate::kCount); ++i) {
      filtered[i] += o.filtered[i];
      exact[i] += o.exact[i];
    }
  }
  std::uint64_t total_exact() const {
    std::uint64_t s = 0;
    for (auto v : exact) s += v;
    return s;
  }
};

}  // namespace nearcap
