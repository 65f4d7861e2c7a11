// The folders are layers (README "Layout"): a file may include headers of its
// own layer and of the layers before it, never of a later one.  So the exact
// kernel includes nothing from gl/, judge/ or render/, and io/ nothing from
// the float pipeline.  Checked over every header and source file.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace nearcap {
namespace {

namespace fs = std::filesystem;

// "front" is the front door, include/nearcap/nearcap.hpp and src/nearcap.cpp:
// files at the root, but the last layer of the core library (it calls the
// exact kernel, the emulation, the judge and the policy), before the viewer
// and the program, which may use it.
const std::map<std::string, int> kLayer = {{"", 0},       {"numeric", 1},  {"scene", 2}, {"exact", 3},  {"io", 4},
                                           {"gl", 5},     {"raytrace", 6}, {"judge", 7}, {"render", 8}, {"analysis", 9},
                                           {"front", 10}, {"view", 11},    {"cli", 12}};

// "exact" for include/nearcap/exact/x.hpp and src/exact/x.cpp; "front" for
// the front door; "" for the other files at the root.
std::string layer_of(const fs::path& relative) {
  if (relative == "nearcap.hpp" || relative == "nearcap.cpp") return "front";
  const auto first = relative.begin();
  if (std::next(first) == relative.end()) return "";
  return first->string();
}

TEST(Layering, EveryIncludePointsToTheSameOrAnEarlierLayer) {
  const fs::path root(NEARCAP_SOURCE_DIR);
  std::size_t files = 0, includes = 0;
  for (const auto& [base, prefix] :
       {std::pair<fs::path, std::string>{root / "include/nearcap", "include"}, {root / "src", "src"}}) {
    for (const auto& entry : fs::recursive_directory_iterator(base)) {
      if (!entry.is_regular_file()) continue;
      const fs::path rel = fs::relative(entry.path(), base);
      const std::string from = layer_of(rel);
      ASSERT_TRUE(kLayer.count(from)) << "unknown layer folder " << from << " (" << rel << "): add it to kLayer";
      ++files;
      std::ifstream in(entry.path());
      std::string line;
      while (std::getline(in, line)) {
        // #include "nearcap/LAYER/..." (std::regex is avoided: GCC 12 warns
        // inside <regex> under the sanitizers, and warnings are errors).
        const std::string prefix_text = "#include \"nearcap/";
        const auto at = line.find(prefix_text);
        if (at == std::string::npos || line.find_first_not_of(" \t") != at) continue;
        const auto start = at + prefix_text.size(), end = line.find('"', start);
        if (end == std::string::npos) continue;
        ++includes;
        const std::string to = layer_of(fs::path(line.substr(start, end - start)));
        ASSERT_TRUE(kLayer.count(to)) << rel << " includes an unknown layer: " << line;
        EXPECT_LE(kLayer.at(to), kLayer.at(from))
            << prefix << "/" << rel.string() << " (" << from << ") includes a later layer: " << line;
      }
    }
  }
  EXPECT_GT(files, 60u);
  EXPECT_GT(includes, 100u);
}

// The ray tracer is a library of its own (nearcap::raytrace, Embree): the
// front door's headers, everything nearcap.hpp includes, name none of its
// headers, so a program of the core library alone never declares a function
// it cannot link.
TEST(Layering, TheFrontDoorIncludesNothingOfTheRaytraceLibrary) {
  const fs::path include(std::string(NEARCAP_SOURCE_DIR) + "/include");
  std::set<std::string> seen;
  std::vector<std::string> todo{"nearcap/nearcap.hpp"};
  while (!todo.empty()) {
    const std::string header = todo.back();
    todo.pop_back();
    if (!seen.insert(header).second) continue;
    EXPECT_NE(layer_of(fs::path(header.substr(std::string("nearcap/").size()))), "raytrace")
        << header << " is included by the front door";
    std::ifstream in(include / header);
    ASSERT_TRUE(in) << header;
    std::string line;
    while (std::getline(in, line)) {
      const std::string prefix_text = "#include \"nearcap/";
      const auto at = line.find(prefix_text);
      if (at == std::string::npos || line.find_first_not_of(" \t") != at) continue;
      const auto start = at + std::string("#include \"").size(), end = line.find('"', start);
      if (end != std::string::npos) todo.push_back(line.substr(start, end - start));
    }
  }
  EXPECT_GT(seen.size(), 10u);
}

}  // namespace
}  // namespace nearcap
