// nearcap frame PATH --frame K [--out FILE]: one frame of a camera path as a
// scene file, to replay it alone with the other commands.
#include <iostream>
#include <vector>

#include "cli_commands.hpp"
#include "command_output.hpp"
#include "nearcap/analysis/camera_path.hpp"
#include "nearcap/error.hpp"
#include "nearcap/io/scene_file.hpp"
#include "subcommand.hpp"

namespace nearcap::cli {
namespace {

struct FrameOptions {
  std::string path;
  int frame = 0;
  int width = 0, height = 0;  // 0: the path's
  std::string out;
};

void run(const std::string& path_file, int frame, int width, int height, const std::string& out) {
  analysis::CameraPath path = load_camera_path_file(path_file);
  if (width > 0) path.width = width;
  if (height > 0) path.height = height;
  if (frame < 0 || frame >= path.frames)
    throw Error(ErrorKind::Usage, path_file + ": --frame " + std::to_string(frame) + " is not in [0, " +
                                      std::to_string(path.frames) + ") (the path has " + std::to_string(path.frames) +
                                      " frames)");
  const std::string json = analysis::path_frame_json(path, frame) + "\n";
  // The frame as every other command reads it: a camera the keyframes
  // interpolate to nothing drawable (a zero up vector, the eye on the
  // target) is refused here, naming the path and the frame.
  const Scene scene = parse_scene(json, path_file + " frame " + std::to_string(frame), ".");
  if (!out.empty()) {
    std::vector<CommandInput> inputs{{path_file, "camera path file"}, {path.scene_file, "scene file"}};
    for (const SceneObject& o : scene.objects) inputs.push_back({o.mesh_path, "mesh file"});
    refuse_replacing_inputs(out, inputs);
  }
  if (out.empty())
    std::cout << json;
  else
    io::write_output_files({{out, json}});
}

}  // namespace

void register_frame(CLI::App& app) {
  auto [cmd, o] = add_subcommand<FrameOptions>(
      app, "frame", "one frame of a camera path (data/paths/) as a scene file: stdout, or --out FILE",
      [](const FrameOptions& f) { run(f.path, f.frame, f.width, f.height, f.out); });
  cmd.add_option("path", o.path, "camera path file (JSON)")->required();
  cmd.add_option("--frame", o.frame, "frame index (0 = the first)")
      ->transform(integer_in(0, std::numeric_limits<int>::max()))
      ->required();
  cmd.add_option("--width", o.width, "viewport width (default: the path's)")
      ->transform(integer_in(1, kMaxViewportPixels));
  cmd.add_option("--height", o.height, "viewport height (default: the path's)")
      ->transform(integer_in(1, kMaxViewportPixels));
  cmd.add_option("--out", o.out, "write the scene file here (default: stdout)");
}

}  // namespace nearcap::cli
