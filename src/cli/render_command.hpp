// The private parts of `nearcap render` shared by its two paths: the
// options, and the lit frames (render_lit.cpp) beside --compare
// (render_command.cpp).
#pragma once

#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "cli_commands.hpp"
#include "nearcap/render/egl_context.hpp"
#include "nearcap/render/glsl_shadow_programs.hpp"

namespace nearcap::cli {

struct RenderOptions {
  std::string scene;
  std::string path;  // a camera path instead of a scene
  std::size_t light = 0;
  bool light_given = false;
  std::string method = "all";
  std::string policy = shipped_data_dir() + "/policy.json";
  bool policy_given = false;  // --policy on the command line
  bool compare = false;
  bool table = false;    // with --compare: a table instead of the JSON line
  bool stencil = false;  // the lit frames' stencils too, per light, as 16-bit PGM
  bool bench = false;    // per-pass times, DIR/bench.csv and (along a path) DIR/bench.png
  bool one_sided_stencil = false;
  bool side_strips = false;
  render::VertexStage vertex_stage = render::VertexStage::Glsl;
  std::string out;
  EmulationOptions emulation;
  double max_memory_gb = 0;
};

// The stencil as the reference's 16-bit PGM (top row first).
std::string stencil_pgm(int width, int height, const std::vector<std::uint8_t>& stencil);

// render.json and the line on stdout: the GL that drew (`context`), the
// vertex stage and a record per method.
nlohmann::json render_json(const render::EglContext& context, render::VertexStage stage,
                           const std::vector<nlohmann::json>& methods);

// Without --compare: the lit frames (render_lit.cpp).
void run_lit(const RenderOptions& o);

}  // namespace nearcap::cli
