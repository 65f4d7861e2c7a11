// nearcap cap SCENE --light K [--out FILE] [--svg FILE]: the exact near-cap.
//
// Everything is computed (and the SVG drawn) before anything is written, and
// files are written atomically: an error leaves no output.  JSON as in the
// README; "ms" is the time of NearCap::build alone (light facing, silhouettes,
// exact curves, arrangement, counts), "exact_fallbacks" the predicate calls
// the double filters could not decide (the arrangement's exact constructions
// are not fallbacks: they are listed under "filter" as "arrangement").
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdint>
#include <iostream>
#include <map>

#include "cli_commands.hpp"
#include "command_output.hpp"
#include "nearcap/exact/near_cap.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/judge/near_cap_svg.hpp"
#include "subcommand.hpp"

namespace nearcap::cli {
namespace {

nlohmann::json point_json(const NearCapPoint& p) {
  return {{"x", p.x.get_str()}, {"y", p.y.get_str()}, {"xd", p.x.get_d()}, {"yd", p.y.get_d()}};
}
nlohmann::json ring_json(const std::vector<NearCapPoint>& ring) {
  nlohmann::json j = nlohmann::json::array();
  for (const NearCapPoint& p : ring) j.push_back(point_json(p));
  return j;
}

struct CapOptions {
  std::string scene;
  std::size_t light = 0;
  std::string out;
  std::string svg;
};

void run(const std::string& scene_path, std::size_t light, const std::string& out, const std::string& svg_path) {
  const Scene scene = load_scene(scene_path);
  for (const std::string& file : {out, svg_path})
    if (!file.empty()) refuse_replacing_inputs(file, scene_inputs(scene));
  check_light_index(scene, light);
  const CameraSpaceScene cs(scene);
  const auto t0 = std::chrono::steady_clock::now();
  FilterStats stats;
  const NearCap cap = NearCap::build(cs, light, &stats);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();

  const Frustum& fr = scene.camera.frustum;
  nlohmann::json j;
  j["scene"] = scene.source;
  j["light"] = light;
  j["near_rectangle"] = {
      {"left", fr.left}, {"right", fr.right}, {"bottom", fr.bottom}, {"top", fr.top}, {"z", -fr.near}};
  j["faces"] = nlohmann::json::array();
  for (const NearCapFace& f : cap.faces()) {
    nlohmann::json holes = nlohmann::json::array();
    for (const auto& h : f.holes) holes.push_back(ring_json(h));
    j["faces"].push_back(
        {{"count", f.count}, {"outer", ring_json(f.outer)}, {"holes", holes}, {"area", f.area_estimate}});
  }
  j["max_count"] = cap.max_count();
  j["curves"] = {{"silhouette", cap.silhouette_curves()},
                 {"near_plane_cuts", cap.near_plane_cuts()},
                 {"arrangement_edges", cap.arrangement_edges()}};
  nlohmann::json filter = nlohmann::json::object();
  std::uint64_t fallbacks = 0;
  for (int p = 0; p < static_cast<int>(Predicate::kCount); ++p) {
    if (stats.filtered[p] + stats.exact[p] == 0) continue;
    filter[std::string(to_string(static_cast<Predicate>(p)))] = {{"filtered", stats.filtered[p]},
                                                                 {"exact", stats.exact[p]}};
    if (static_cast<Predicate>(p) != Predicate::Arrangement) fallbacks += stats.exact[p];
  }
  j["exact_fallbacks"] = fallbacks;
  j["filter"] = filter;
  j["ms"] = ms;
  const std::string svg = svg_path.empty()
                              ? std::string()
                              : near_cap_svg(cap, scene.camera, scene.source + ", light " + std::to_string(light));
  std::vector<io::OutputFile> files;
  if (!out.empty()) files.push_back({out, json_file_text(j)});
  if (!svg_path.empty()) files.push_back({svg_path, svg});
  io::write_output_files(files);
  if (out.empty()) {
    print_json_line(j);
  } else {
    std::map<std::size_t, double> area;
    for (const NearCapFace& f : cap.faces()) area[f.count] += f.area_estimate;
    const double total = (fr.right - fr.left) * (fr.top - fr.bottom);
    std::cout << "near-cap of " << scene.source << ", light " << light << ": " << cap.faces().size() << " face(s), "
              << cap.silhouette_curves() << " silhouette curve(s), " << cap.near_plane_cuts() << " near-plane cut(s), "
              << ms << " ms\n";
    for (const auto& [count, a] : area)
      std::cout << "  count " << count << ": " << 100.0 * a / total << "% of the near rectangle\n";
  }
}

}  // namespace

void register_cap(CLI::App& app) {
  auto [cmd, o] = add_subcommand<CapOptions>(
      app, "cap",
      "the exact near-cap: faces of the near rectangle with their counts (JSON), optionally a picture (SVG)",
      [](const CapOptions& c) { run(c.scene, c.light, c.out, c.svg); });
  add_scene_argument(cmd, o.scene)->required();
  add_light_option(cmd, o.light);
  cmd.add_option("--out", o.out, "write the JSON here (default: stdout)");
  cmd.add_option("--svg", o.svg, "write an SVG picture here");
}

}  // namespace nearcap::cli
