// nearcap frame PATH --frame K [--out FILE]: one frame of a camera path as a
// scene file, to replay it alone with the other commands.
#include <iostream>

#include "cli_commands.hpp"
#include "nearcap/analysis/camera_path.hpp"
#include "nearcap/error.hpp"

namespace nearcap::cli {
namespace {

void run(const std::string& path_file, int frame, int width, int height, const std::string& out) {
  analysis::CameraPath path = analysis::load_camera_path(path_file);
  if (width > 0) path.width = width;
  if (height > 0) path.height = height;
  if (frame < 0 || frame >= path.frames)
    throw Error(ErrorKind::Usage, path_file + ": --frame " + std::to_string(frame) + " is not in [0, " +
                                      std::to_string(path.frames) + ") (the path has " + std::to_string(path.frames) +
                                      " frames)");
  const std::string json = analysis::path_frame_json(path, frame) + "\n";
  if (out.empty())
    std::cout << json;
  else
    io::write_output_files({{out, json}});
}

}  // namespace

void register_frame(CLI::App& app) {
  auto* cmd =
      app.add_subcommand("frame", "one frame of a camera path (data/paths/) as a scene file: stdout, or --out FILE");
  auto path = std::make_shared<std::string>();
  auto frame = std::make_shared<int>(0);
  auto out = std::make_shared<std::string>();
  cmd->add_option("path", *path, "camera path file (JSON)")->required();
  cmd->add_option("--frame", *frame, "frame index (0 = the first)")
      ->transform(integer_in(0, std::numeric_limits<int>::max()))
      ->required();
  auto width = std::make_shared<int>(0), height = std::make_shared<int>(0);
  cmd->add_option("--width", *width, "viewport width (default: the path's)")
      ->transform(integer_in(1, kMaxViewportPixels));
  cmd->add_option("--height", *height, "viewport height (default: the path's)")
      ->transform(integer_in(1, kMaxViewportPixels));
  cmd->add_option("--out", *out, "write the scene file here (default: stdout)");
  cmd->callback([path, frame, width, height, out] { run(*path, *frame, *width, *height, *out); });
}

}  // namespace nearcap::cli
