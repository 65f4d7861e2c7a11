// The library example the documentation shows is the file the suite builds
// and runs (examples/library_example.cpp, LibraryExample.Runs): docs/library.md
// holds the whole file, the README an excerpt of whole lines of it; neither
// can drift from the code that is compiled.
#include <gtest/gtest.h>

#include <string>

#include "cli_support.hpp"

namespace nearcap {
namespace {

// The text between `<!-- KIND: examples/library_example.cpp -->` and its end
// marker, the fenced block's body; empty when the markers are missing.
std::string marked_block(const std::string& doc, const std::string& kind) {
  const std::string open = "<!-- " + kind + ": examples/library_example.cpp -->\n```cpp\n",
                    close = "```\n<!-- end " + kind + " -->";
  const auto begin = doc.find(open);
  if (begin == std::string::npos) return {};
  const auto end = doc.find(close, begin);
  if (end == std::string::npos) return {};
  return doc.substr(begin + open.size(), end - begin - open.size());
}

TEST(ReadmeExample, LibraryPageHoldsTheBuiltExample) {
  const std::string root(NEARCAP_SOURCE_DIR);
  const std::string code = test::slurp(root + "/examples/library_example.cpp");
  const std::string shown = marked_block(test::slurp(root + "/docs/library.md"), "example");
  ASSERT_FALSE(shown.empty()) << "docs/library.md lost its example markers";
  EXPECT_EQ(shown, code)
      << "docs/library.md's example differs from examples/library_example.cpp: copy the file into docs/library.md";
}

TEST(ReadmeExample, ReadmeExcerptIsFromTheBuiltExample) {
  const std::string root(NEARCAP_SOURCE_DIR);
  const std::string code = test::slurp(root + "/examples/library_example.cpp");
  const std::string shown = marked_block(test::slurp(root + "/README.md"), "excerpt");
  ASSERT_FALSE(shown.empty()) << "README.md lost its excerpt markers";
  // Whole lines: the excerpt starts at the beginning of a line of the file.
  const auto at = code.find(shown);
  EXPECT_TRUE(at != std::string::npos && (at == 0 || code[at - 1] == '\n'))
      << "README.md's excerpt is not a run of whole lines of examples/library_example.cpp: copy them again";
}

}  // namespace
}  // namespace nearcap
