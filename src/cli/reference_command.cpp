// nearcap reference SCENE --light K --out DIR: the exact per-pixel reference.
#include <nlohmann/json.hpp>

#include <filesystem>

#include "cli_commands.hpp"
#include "command_output.hpp"
#include "nearcap/error.hpp"
#include "nearcap/exact/pixel_reference.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/judge/reference_images.hpp"
#include "subcommand.hpp"

namespace nearcap::cli {
namespace {

nlohmann::json summary_json(const Scene& scene, const PixelReference& ref) {
  std::size_t seen = 0, shadowed = 0, cap_nonzero = 0;
  std::uint32_t max_cap = 0, max_stencil = 0;
  for (std::size_t k = 0; k < ref.cap.size(); ++k) {
    max_cap = std::max(max_cap, ref.cap[k]);
    if (ref.cap[k] > 0) ++cap_nonzero;
    if (ref.stencil[k] == PixelReference::kNothingSeen) continue;
    ++seen;
    if (ref.stencil[k] > 0) ++shadowed;
    max_stencil = std::max(max_stencil, ref.stencil[k]);
  }
  nlohmann::json filter = nlohmann::json::object();
  for (int p = 0; p < static_cast<int>(Predicate::kCount); ++p)
    if (ref.stats.filtered[p] + ref.stats.exact[p] > 0)
      filter[std::string(to_string(static_cast<Predicate>(p)))] = {{"filtered", ref.stats.filtered[p]},
                                                                   {"exact", ref.stats.exact[p]}};
  return {{"scene", scene.source},
          {"light", ref.light},
          {"width", ref.width},
          {"height", ref.height},
          {"pixels_seen", seen},
          {"pixels_shadowed", shadowed},
          {"pixels_cap_nonzero", cap_nonzero},
          {"max_cap", max_cap},
          {"max_stencil", max_stencil},
          {"setup_ms", ref.setup_ms},
          {"trace_ms", ref.trace_ms},
          {"filter", filter}};
}

// Memory per pixel beyond the fixed 64 MB: the reference's cap and stencil
// counts, the per-pixel scratch of the trace, the encoded images.  The peak
// measured at 2048x2048 is 18.5 bytes per pixel beyond 64 MB
// (docs/findings/exact-speed.md, "Memory"); 30 leaves room for scenes whose
// trace keeps more per pixel.
constexpr double kReferenceBytesPerPixel = 30;

struct ReferenceOptions {
  std::string scene;
  std::size_t light = 0;
  std::string out;
  double max_memory_gb = 0;
};

void run(const std::string& scene_path, std::size_t light, const std::string& out_dir, double max_memory_gb) {
  const Scene scene = load_scene(scene_path);
  check_light_index(scene, light);
  check_memory_estimate(scene, "reference", kReferenceBytesPerPixel, max_memory_gb);
  refuse_non_directory(out_dir, "--out");
  const CameraSpaceScene cs(scene);
  const PixelReference ref = compute_pixel_reference(cs, light);
  const nlohmann::json summary = summary_json(scene, ref);
  // Everything is computed and encoded before the first byte is written.
  const std::string cap = cap_pgm(ref), stencil = stencil_pgm(ref), shadow = shadow_png(cs, ref);
  const std::filesystem::path dir(out_dir);
  for (const char* name : {"cap.pgm", "stencil.pgm", "shadow.png", "reference.json"})
    refuse_replacing_inputs((dir / name).string(), scene_inputs(scene));
  io::write_output_files({{(dir / "cap.pgm").string(), cap},
                          {(dir / "stencil.pgm").string(), stencil},
                          {(dir / "shadow.png").string(), shadow},
                          {(dir / "reference.json").string(), json_file_text(summary)}});
  print_json_line(summary);
}

}  // namespace

void register_reference(CLI::App& app) {
  auto [cmd, o] = add_subcommand<ReferenceOptions>(
      app, "reference",
      "exact per-pixel near-cap and stencil counts: DIR/cap.pgm, DIR/stencil.pgm (16-bit, top row first, 65535 = "
      "nothing seen), DIR/shadow.png, DIR/reference.json",
      [](const ReferenceOptions& r) { run(r.scene, r.light, r.out, r.max_memory_gb); });
  add_scene_argument(cmd, o.scene)->required();
  add_light_option(cmd, o.light);
  cmd.add_option("--out", o.out, "output directory (created if missing)")->required();
  add_max_memory_option(cmd, o.max_memory_gb);
}

}  // namespace nearcap::cli
