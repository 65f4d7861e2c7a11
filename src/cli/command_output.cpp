// A command's outputs (see command_output.hpp).
#include "command_output.hpp"

#include <filesystem>
#include <iostream>

#include "nearcap/error.hpp"

#include "cli_commands.hpp"

namespace nearcap::cli {

std::string json_file_text(const nlohmann::json& j) { return json_text(j, 1) + "\n"; }

void print_json_line(const nlohmann::json& j) { std::cout << json_text(j) << "\n"; }

void refuse_replacing_inputs(const std::string& output, const std::vector<CommandInput>& inputs,
                             const std::string& option) {
  for (const CommandInput& in : inputs) {
    std::error_code ec;
    if (output == in.path || (std::filesystem::equivalent(output, in.path, ec) && !ec))
      throw Error(ErrorKind::Usage, (option.empty() ? "" : option + " ") + output + ": this output would replace the " +
                                        in.what + " the command reads (" + in.path + "); name another file");
  }
}

std::vector<CommandInput> scene_inputs(const Scene& scene) {
  std::vector<CommandInput> inputs{{scene.source, "scene file"}};
  for (const SceneObject& o : scene.objects)
    if (!o.mesh_path.empty()) inputs.push_back({o.mesh_path, "mesh file"});
  return inputs;
}

std::vector<CommandInput> sampler_inputs(const analysis::SamplerSpec& spec) {
  std::vector<CommandInput> inputs;
  for (const std::string& file : analysis::sampler_mesh_files(spec)) inputs.push_back({file, "sampler's mesh file"});
  return inputs;
}

std::vector<CommandInput> camera_path_inputs(const analysis::CameraPath& path) {
  std::vector<CommandInput> inputs{{path.source, "camera path file"}, {path.scene_file, "scene file"}};
  // The base scene's text names its meshes by absolute path (load_camera_path checked it loads).
  const nlohmann::json base = nlohmann::json::parse(path.base_scene_json);
  for (const nlohmann::json& o : base.at("objects")) inputs.push_back({o.at("mesh").get<std::string>(), "mesh file"});
  return inputs;
}

void OutputDir::add(const std::string& name, const std::function<std::string()>& make) {
  if (!given()) return;
  refuse_replacing_inputs(path(name), inputs_);
  files_.push_back({path(name), make()});
}

void OutputDir::write(const std::string& json_name, const nlohmann::json& j) {
  if (!given()) return;
  refuse_replacing_inputs(path(json_name), inputs_);
  files_.push_back({path(json_name), json_file_text(j)});
  io::write_output_files(files_);
}

}  // namespace nearcap::cli
