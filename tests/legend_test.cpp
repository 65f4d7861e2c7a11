// Legend strips under the judge's pictures (judge/legend.hpp): text wrapped to
// the image, never the image widened by its text.
#include "nearcap/judge/legend.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

namespace nearcap {
namespace {

std::string joined(const std::vector<std::string>& lines) {
  std::string s;
  for (const std::string& l : lines) s += (s.empty() ? "" : " ") + l;
  return s;
}

TEST(Legend, WrappedLinesFitAndKeepEveryWord) {
  const std::string text =
      "policy (zpplus-corrected on 2 occluders, zfail on 1): 12 wrong (3 lit, 9 shadowed), "
      "4 cracks, 20 count, - near-cap";
  for (const int width : {40, 100, 200, 1000}) {
    const std::vector<std::string> lines = legend::wrap_text(text, width);
    for (const std::string& l : lines) EXPECT_LE(legend::text_width(l), width) << "'" << l << "' at " << width;
    if (width >= 100) {  // every word fits a line: broken at spaces only
      EXPECT_EQ(joined(lines), text) << width;
    }
  }
  EXPECT_EQ(legend::wrap_text(text, 1000).size(), 1u);
  EXPECT_GT(legend::wrap_text(text, 100).size(), 2u);
  // Narrower than "zpplus-corrected": that word is cut, no character lost.
  std::string rejoined;
  for (const std::string& l : legend::wrap_text(text, 40)) rejoined += l;
  std::string letters = text;
  letters.erase(std::remove(letters.begin(), letters.end(), ' '), letters.end());
  rejoined.erase(std::remove(rejoined.begin(), rejoined.end(), ' '), rejoined.end());
  EXPECT_EQ(rejoined, letters);
}

TEST(Legend, AWordWiderThanALineIsCut) {
  const std::string word = "zpplus-corrected-zpplus-corrected";
  const std::vector<std::string> lines = legend::wrap_text(word, 30);
  ASSERT_GT(lines.size(), 1u);
  std::string rejoined;
  for (const std::string& l : lines) {
    EXPECT_LE(legend::text_width(l), 30) << l;
    EXPECT_FALSE(l.empty());
    rejoined += l;
  }
  EXPECT_EQ(rejoined, word);
  // Narrower than one glyph: one character a line, and the text still ends.
  EXPECT_EQ(legend::wrap_text("abc", 1).size(), 3u);
  EXPECT_EQ(legend::wrap_text("", 10), std::vector<std::string>{""});
}

legend::Image grey(int width, int height) {
  return {width, height, std::vector<std::uint8_t>(3 * static_cast<std::size_t>(width) * height, 128)};
}

TEST(Legend, TheStripKeepsTheImageWidthWhateverItsText) {
  const std::vector<legend::Entry> short_entries = {{{255, 0, 0}, "wrong"}};
  const std::vector<legend::Entry> long_entries = {
      {{255, 0, 0}, "boundary noise, lit (exact status not constant over the pixel), and more words to make it long"},
      {{0, 255, 0}, std::string(300, 'x')}};
  const std::string long_title(400, 'w');
  for (const int width : {320, 640, 1280}) {
    const legend::Image a = legend::with_legend(grey(width, 10), "title", short_entries);
    const legend::Image b = legend::with_legend(grey(width, 10), long_title, long_entries);
    EXPECT_EQ(a.width, width);
    EXPECT_EQ(b.width, width);
    EXPECT_GT(b.height, a.height) << "long text grows the strip downwards";
    EXPECT_EQ(b.rgb.size(), 3 * static_cast<std::size_t>(b.width) * b.height);
  }
  // A frame narrower than the narrowest strip: padded to it, text or none.
  EXPECT_EQ(legend::with_legend(grey(64, 48), "", short_entries).width, legend::kMinLegendWidth);
  EXPECT_EQ(legend::with_legend(grey(64, 48), long_title, long_entries).width, legend::kMinLegendWidth);
}

}  // namespace
}  // namespace nearcap
