// The regression corpus (data/regress/regressions.json): every scene gives
// the figures the corpus records for it.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "nearcap/exact/classification.hpp"
#include "nearcap/exact/near_cap.hpp"
#include "nearcap/exact/pixel_reference.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/judge/crack_map.hpp"

namespace nearcap {
namespace {

TEST(RegressionCorpus, EveryEntryKeepsItsFigures) {
  const std::string dir = std::string(NEARCAP_SOURCE_DIR) + "/data/regress/";
  const auto entries = nlohmann::json::parse(test::slurp(dir + "regressions.json"));
  ASSERT_FALSE(entries.empty());
  for (const auto& e : entries) {
    const std::string scene_path = dir + e.at("scene").get<std::string>();
    SCOPED_TRACE(scene_path);
    const Scene scene = load_scene(scene_path);
    const CameraSpaceScene cs(scene);
    const std::size_t light = e.at("light").get<std::size_t>();

    const SceneClassification c = classify_scene(cs);
    std::array<std::size_t, kQuadCaseCount> cases{};
    for (const ObjectClassification& o : c.lights.at(light).objects)
      for (std::size_t k = 0; k < kQuadCaseCount; ++k) cases[k] += o.case_counts[k];
    for (std::size_t k = 0; k < kQuadCaseCount; ++k) {
      const std::string name(to_string(static_cast<QuadCase>(k)));
      EXPECT_EQ(cases[k], e.at("cases").at(name).get<std::size_t>()) << name;
    }

    const PixelReference ref = compute_pixel_reference(cs, light);
    std::size_t seen = 0, shadowed = 0, cap_nonzero = 0;
    std::uint32_t max_cap = 0, max_stencil = 0;
    for (std::size_t k = 0; k < ref.cap.size(); ++k) {
      cap_nonzero += ref.cap[k] > 0;
      max_cap = std::max(max_cap, ref.cap[k]);
      if (ref.stencil[k] == PixelReference::kNothingSeen) continue;
      ++seen;
      shadowed += ref.stencil[k] > 0;
      max_stencil = std::max(max_stencil, ref.stencil[k]);
    }
    const auto& want = e.at("reference");
    EXPECT_EQ(seen, want.at("pixels_seen").get<std::size_t>());
    EXPECT_EQ(shadowed, want.at("pixels_shadowed").get<std::size_t>());
    EXPECT_EQ(cap_nonzero, want.at("pixels_cap_nonzero").get<std::size_t>());
    EXPECT_EQ(max_cap, want.at("max_cap").get<std::uint32_t>());
    EXPECT_EQ(max_stencil, want.at("max_stencil").get<std::uint32_t>());
    EXPECT_LE(ref.stats.exact[static_cast<int>(Predicate::ShadowCrossing)],
              e.at("exact_fallbacks_at_most").get<std::uint64_t>());

    const NearCap cap = NearCap::build(cs, light);
    EXPECT_EQ(cap.faces().size(), e.at("near_cap_faces").get<std::size_t>());

    // Wrong pixels per float method (default emulation settings), where recorded.
    if (e.contains("cracks"))
      for (const auto& [name, figures] : e.at("cracks").items()) {
        SCOPED_TRACE(name);
        const auto method = gl::shadow_method_from_string(name);
        ASSERT_TRUE(method.has_value());
        const CrackReport r = judge_frame(gl::render_shadow_frame(scene, light, *method), ref);
        EXPECT_EQ(r.wrong, figures.at("wrong").get<std::size_t>());
        EXPECT_EQ(r.count_mismatch, figures.at("count_mismatch").get<std::size_t>());
        if (figures.at("cap_mismatch").is_null()) {
          EXPECT_FALSE(r.cap_mismatch.has_value());
        } else {
          ASSERT_TRUE(r.cap_mismatch.has_value());
          EXPECT_EQ(*r.cap_mismatch, figures.at("cap_mismatch").get<std::size_t>());
        }
      }
  }
}

}  // namespace
}  // namespace nearcap
