// nearcap/judge/word_wrap.hpp — text cut into lines that fit a width.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace nearcap {

// The words of `text` (split at spaces) joined into lines that `fits`
// accepts, each line as full as it can be.  A word that fits no line on its
// own is cut between characters where it stops fitting (at least one
// character a line, so that the text always ends).  Never empty: "" gives one
// empty line.  The measure of a line (glyph pixels, SVG units) is the caller's.
std::vector<std::string> wrap_words(const std::string& text, const std::function<bool(const std::string&)>& fits);

}  // namespace nearcap
