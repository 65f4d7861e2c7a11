// Every public header opens with a banner that names its own include path,
// `// nearcap/LAYER/name.hpp — what it holds`, so a reader who meets the
// first line of a file (in a diff, a search hit, an installed copy) knows the
// #include that reaches it.  Checked over every header under include/nearcap.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace nearcap {
namespace {

namespace fs = std::filesystem;

// The path a banner names: the text between "// " and " — " on the first line,
// or the whole first line (so the message shows it) when it has no banner.
std::string banner_path(const std::string& first_line) {
  const std::string open = "// ", dash = " \xE2\x80\x94 ";  // U+2014 EM DASH
  if (first_line.compare(0, open.size(), open) != 0) return first_line;
  const auto end = first_line.find(dash, open.size());
  if (end == std::string::npos) return first_line;
  return first_line.substr(open.size(), end - open.size());
}

TEST(HeaderBanner, BannerOfAHeaderLineIsItsPath) {
  EXPECT_EQ(banner_path("// nearcap/exact/near_cap.hpp \xE2\x80\x94 the true near-cap"), "nearcap/exact/near_cap.hpp");
  EXPECT_EQ(banner_path("// no dash here"), "// no dash here");
  EXPECT_EQ(banner_path("#pragma once"), "#pragma once");
}

TEST(HeaderBanner, EveryPublicHeaderNamesItsOwnPath) {
  const fs::path include = fs::path(NEARCAP_SOURCE_DIR) / "include";
  std::size_t headers = 0;
  for (const auto& entry : fs::recursive_directory_iterator(include / "nearcap")) {
    if (!entry.is_regular_file() || entry.path().extension() != ".hpp") continue;
    ++headers;
    const std::string path = fs::relative(entry.path(), include).generic_string();
    std::ifstream in(entry.path());
    std::string first;
    std::getline(in, first);
    EXPECT_EQ(banner_path(first), path) << "include/" << path << "'s first line names another path: " << first;
  }
  EXPECT_GT(headers, 60u);  // the walk reached the headers, not an empty or moved folder
}

}  // namespace
}  // namespace nearcap
