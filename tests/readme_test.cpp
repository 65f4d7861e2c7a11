// The README's library example is the file the suite builds and runs
// (examples/library_example.cpp, LibraryExample.Runs): the copy cannot drift.
#include <gtest/gtest.h>

#include <string>

#include "cli_support.hpp"

namespace nearcap {
namespace {

TEST(ReadmeExample, IsTheBuiltExample) {
  const std::string root(NEARCAP_SOURCE_DIR);
  const std::string readme = test::slurp(root + "/README.md");
  const std::string code = test::slurp(root + "/examples/library_example.cpp");
  const std::string open = "<!-- example: examples/library_example.cpp -->\n```cpp\n",
                    close = "```\n<!-- end example -->";
  const auto begin = readme.find(open);
  ASSERT_NE(begin, std::string::npos) << "README.md lost its example marker";
  const auto end = readme.find(close, begin);
  ASSERT_NE(end, std::string::npos);
  EXPECT_EQ(readme.substr(begin + open.size(), end - begin - open.size()), code)
      << "README.md's example differs from examples/library_example.cpp: copy the file into the README";
}

}  // namespace
}  // namespace nearcap
