// nearcap classify SCENE [--json]: silhouettes and A-D cases, exact vs engine.
#include <nlohmann/json.hpp>

#include <chrono>
#include <iostream>

#include "cli_commands.hpp"
#include "command_output.hpp"
#include "nearcap/exact/classification.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/judge/case_comparison.hpp"
#include "subcommand.hpp"

namespace nearcap::cli {
namespace {

nlohmann::json cases_json(const std::array<std::size_t, kQuadCaseCount>& counts) {
  nlohmann::json j = nlohmann::json::object();
  for (std::size_t c = 0; c < kQuadCaseCount; ++c) j[std::string(to_string(static_cast<QuadCase>(c)))] = counts[c];
  return j;
}

struct ClassifyOptions {
  std::string scene;
  bool json = false;
};

void run(const std::string& scene_path, bool as_json) {
  const Scene scene = load_scene(scene_path);
  const CameraSpaceScene cs(scene);
  const SceneClassification result = classify_scene(cs);
  const CaseComparison engine = compare_engine_cases(cs, result);

  if (as_json) {
    nlohmann::json root;
    root["lights"] = nlohmann::json::array();
    for (const LightClassification& lc : result.lights) {
      nlohmann::json jl;
      jl["light"] = lc.light;
      jl["light_in_near_plane"] = lc.light_in_near_plane;
      jl["objects"] = nlohmann::json::array();
      for (std::size_t k = 0; k < lc.objects.size(); ++k) {
        const ObjectClassification& oc = lc.objects[k];
        const ObjectCaseComparison& cmp = engine.lights[lc.light][k];
        nlohmann::json jo;
        jo["object"] = oc.object;
        jo["silhouette_edges"] = oc.edges.size();
        jo["cases"] = cases_json(oc.case_counts);
        jo["edge_on_triangles"] = oc.edge_on_triangles;
        const EngineDisagreement& d = cmp.disagreement;
        jo["engine_disagreements"] = {{"total", d.total()},
                                      {"silhouette_missed", d.silhouette_missed},
                                      {"silhouette_extra", d.silhouette_extra},
                                      {"case_mismatch", d.case_mismatch},
                                      {"facing_mismatch", d.facing_mismatch}};
        nlohmann::json edges = nlohmann::json::array();
        for (std::size_t e = 0; e < oc.edges.size(); ++e) {
          const ClassifiedEdge& ce = oc.edges[e];
          nlohmann::json je;
          je["v"] = {std::min(ce.edge.a, ce.edge.d), std::max(ce.edge.a, ce.edge.d)};
          je["case"] = std::string(to_string(ce.exact));
          if (cmp.edges[e].found)
            je["engine_case"] = std::string(to_string(cmp.edges[e].engine));
          else
            je["engine_case"] = nullptr;
          edges.push_back(std::move(je));
        }
        jo["edges"] = std::move(edges);
        jl["objects"].push_back(std::move(jo));
      }
      root["lights"].push_back(std::move(jl));
    }
    nlohmann::json filter = nlohmann::json::object();
    for (int p = 0; p < static_cast<int>(Predicate::kCount); ++p)
      filter[std::string(to_string(static_cast<Predicate>(p)))] = {{"filtered", result.stats.filtered[p]},
                                                                   {"exact", result.stats.exact[p]}};
    root["filter"] = filter;
    print_json_line(root);
    return;
  }
  std::cout << "scene " << scene.source << ": " << scene.lights.size() << " light(s), " << scene.objects.size()
            << " object(s)\n";
  std::cout << "light object  silhouette      A      B     C1     C2      D  degen  engine-disagree\n";
  for (const LightClassification& lc : result.lights) {
    for (std::size_t k = 0; k < lc.objects.size(); ++k) {
      const ObjectClassification& oc = lc.objects[k];
      char line[256];
      std::snprintf(line, sizeof line, "%5zu %6zu %11zu %6zu %6zu %6zu %6zu %6zu %6zu  %15zu\n", lc.light, oc.object,
                    oc.edges.size(), oc.case_counts[0], oc.case_counts[1], oc.case_counts[2], oc.case_counts[3],
                    oc.case_counts[4], oc.case_counts[5], engine.lights[lc.light][k].disagreement.total());
      std::cout << line;
    }
  }
  std::cout << "exact fallbacks: " << result.stats.total_exact() << " predicate calls needed rationals\n";
  print_case_legend(std::cout);
}

}  // namespace

void register_classify(CLI::App& app) {
  auto [cmd, o] =
      add_subcommand<ClassifyOptions>(app, "classify", "silhouette edges and ZP+ cases A-D per light and occluder",
                                      [](const ClassifyOptions& c) { run(c.scene, c.json); });
  add_scene_argument(cmd, o.scene)->required();
  cmd.add_flag("--json", o.json, "print every edge as JSON");
}

}  // namespace nearcap::cli
