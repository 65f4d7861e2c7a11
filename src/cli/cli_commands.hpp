// The subcommands of the nearcap program, one file each.
#pragma once

#include <CLI/CLI.hpp>

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "nearcap/scene.hpp"

namespace nearcap::cli {

void register_classify(CLI::App& app);
void register_cap(CLI::App& app);
void register_reference(CLI::App& app);
void register_cracks(CLI::App& app);

// Throws Error(Usage) when `light` is not an index of scene.lights.
void check_light_index(const Scene& scene, std::size_t light);

// Several outputs of one command: every file is written to a temporary first,
// and only when all succeeded are they renamed into place.
void write_files_atomically(const std::vector<std::pair<std::string, std::string>>& files);

}  // namespace nearcap::cli
