// A command's outputs (see command_output.hpp).
#include "command_output.hpp"

#include <iostream>

#include "cli_commands.hpp"

namespace nearcap::cli {

std::string json_file_text(const nlohmann::json& j) { return json_text(j, 1) + "\n"; }

void print_json_line(const nlohmann::json& j) { std::cout << json_text(j) << "\n"; }

void OutputDir::add(const std::string& name, const std::function<std::string()>& make) {
  if (given()) files_.push_back({path(name), make()});
}

void OutputDir::write(const std::string& json_name, const nlohmann::json& j) {
  if (!given()) return;
  files_.push_back({path(json_name), json_file_text(j)});
  io::write_output_files(files_);
}

}  // namespace nearcap::cli
