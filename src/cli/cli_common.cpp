#include <cstdio>
#include <filesystem>
#include <fstream>

#include "cli_commands.hpp"
#include "nearcap/error.hpp"

namespace nearcap::cli {

void check_light_index(const Scene& scene, std::size_t light) {
  if (light >= scene.lights.size())
    throw Error(ErrorKind::Usage, scene.source + ": --light " + std::to_string(light) +
                                      " is out of range (the scene has " + std::to_string(scene.lights.size()) +
                                      " light(s))");
}

void write_files_atomically(const std::vector<std::pair<std::string, std::string>>& files) {
  // All temporaries first: a failure before the renames leaves no output.
  std::vector<std::string> temporaries;
  auto cleanup = [&] {
    for (const std::string& t : temporaries) std::remove(t.c_str());
  };
  for (const auto& [path, content] : files) {
    const std::string tmp = path + ".tmp-nearcap";
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) {
      cleanup();
      throw Error(ErrorKind::Io, path + ": cannot write the output file");
    }
    temporaries.push_back(tmp);
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    out.close();
    if (!out) {
      cleanup();
      throw Error(ErrorKind::Io, path + ": write failed");
    }
  }
  for (std::size_t k = 0; k < files.size(); ++k) {
    std::error_code ec;
    std::filesystem::rename(temporaries[k], files[k].first, ec);
    if (ec) {
      cleanup();
      throw Error(ErrorKind::Io, files[k].first + ": cannot move the output into place: " + ec.message());
    }
  }
}

}  // namespace nearcap::cli
