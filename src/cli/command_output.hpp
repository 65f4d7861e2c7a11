// A command's outputs: the files it writes into its --out DIR, all or
// nothing, and the JSON it prints on stdout.
#pragma once

#include <nlohmann/json.hpp>

#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "nearcap/analysis/camera_path.hpp"
#include "nearcap/analysis/hard_case_sampler.hpp"
#include "nearcap/io/output_files.hpp"
#include "nearcap/scene/scene.hpp"

namespace nearcap::cli {

// The text of a JSON output file: `j` indented by one space (json_text),
// ending in a newline.
std::string json_file_text(const nlohmann::json& j);

// Prints `j` on stdout as one line of JSON.
void print_json_line(const nlohmann::json& j);

// A file a command reads, which none of its outputs may replace: its path
// and what it is ("scene file", "camera path file").
struct CommandInput {
  std::string path, what;
};

// Throws Error(Usage) where `output` names the same file as one of `inputs`
// (through a link too), before anything is written: a command never
// replaces what it reads.  `option`, where given, is named before the path
// ("--write-policy").
void refuse_replacing_inputs(const std::string& output, const std::vector<CommandInput>& inputs,
                             const std::string& option = "");

// A scene's files: the scene file and each object's mesh file.
std::vector<CommandInput> scene_inputs(const Scene& scene);

// The mesh files a sampler with `spec` may read (the bundled meshes).
std::vector<CommandInput> sampler_inputs(const analysis::SamplerSpec& spec);

// A camera path's files: the path file, its base scene and the base scene's
// mesh files.
std::vector<CommandInput> camera_path_inputs(const analysis::CameraPath& path);

// The files of a command's --out DIR, gathered while the command runs and
// written together at its end by io::write_output_files (every file or
// none).  Without --out (an empty DIR) nothing is gathered or written, and
// no output's bytes are made.
class OutputDir {
 public:
  // `inputs`: the files none of DIR's may replace (refuse_replacing_inputs).
  explicit OutputDir(const std::string& dir, std::vector<CommandInput> inputs = {})
      : dir_(dir), inputs_(std::move(inputs)) {}
  bool given() const { return !dir_.empty(); }
  // DIR/name.
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  // DIR/name with the bytes that `make` returns; `make` runs only with a DIR.
  void add(const std::string& name, const std::function<std::string()>& make);
  // DIR/json_name with `j`'s text (json_file_text), then every file written.
  void write(const std::string& json_name, const nlohmann::json& j);

 private:
  std::filesystem::path dir_;
  std::vector<CommandInput> inputs_;
  std::vector<io::OutputFile> files_;
};

}  // namespace nearcap::cli
