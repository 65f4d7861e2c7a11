#include <unistd.h>

#include <algorithm>
#include <cstdio>

#include "cli_commands.hpp"
#include "nearcap/error.hpp"

namespace nearcap::cli {

std::string subcommand_names(const CLI::App& app) {
  std::string names;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
    names += (names.empty() ? "" : ", ") + sub->get_name();
  return names;
}

void add_light_option(CLI::App& cmd, std::size_t& light) {
  const CLI::Validator digits(
      [](std::string& value) -> std::string {
        const bool ok = !value.empty() && value.size() <= 9 &&
                        std::all_of(value.begin(), value.end(), [](char c) { return c >= '0' && c <= '9'; });
        return ok ? std::string() : "'" + value + "' is not a light index (a non-negative integer)";
      },
      "INDEX");
  cmd.add_option("--light", light, "index of the light in the scene's list (0, 1, ...)")->required()->check(digits);
}

void add_max_memory_option(CLI::App& cmd, double& max_memory_gb) {
  cmd.add_option("--max-memory", max_memory_gb,
                 "refuse a frame whose estimated memory exceeds this many GB (default: 3/4 of the machine's memory)")
      ->check(CLI::PositiveNumber);
}

void check_memory_estimate(const Scene& scene, const std::string& command, double bytes_per_pixel,
                           double max_memory_gb) {
  const double pixels = static_cast<double>(scene.camera.width) * scene.camera.height;
  const double estimate = 64e6 + bytes_per_pixel * pixels;
  double limit = max_memory_gb * 1e9;
  if (limit <= 0) {
    const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
    limit = pages > 0 && page > 0 ? 0.75 * static_cast<double>(pages) * static_cast<double>(page) : 8e9;
  }
  if (estimate <= limit) return;
  char message[320];
  std::snprintf(message, sizeof message,
                "%s: %s at %dx%d needs about %.1f GB (%.0f bytes per pixel), over the limit of %.1f GB; lower "
                "width/height in the scene, or raise the limit with --max-memory GB",
                scene.source.c_str(), command.c_str(), scene.camera.width, scene.camera.height, estimate / 1e9,
                bytes_per_pixel, limit / 1e9);
  throw Error(ErrorKind::Resource, message);
}

void print_case_legend(std::ostream& out) {
  out << "cases: where the camera's near plane cuts a silhouette edge's infinite side quad (ZP+ section 5)\n"
         "  A   not at all: nothing to correct\n"
         "  B   both infinite edges: the clipped vertices move to their near-cap counterparts (exact)\n"
         "  C1  an infinite edge and the silhouette edge: counterparts plus a corrective quad\n"
         "  C2  an infinite edge and the edge at infinity: counterparts plus a corrective quad\n"
         "  D   the silhouette edge and the edge at infinity (light near the near plane): ZP+ switches to Z-fail\n"
         "  degen(erate)  the plane holds a quad vertex or is parallel to an infinite edge\n";
}

void check_light_index(const Scene& scene, std::size_t light) {
  if (light >= scene.lights.size())
    throw Error(ErrorKind::Usage, scene.source + ": --light " + std::to_string(light) +
                                      " is out of range (the scene has " + std::to_string(scene.lights.size()) +
                                      " light(s))");
}

}  // namespace nearcap::cli
