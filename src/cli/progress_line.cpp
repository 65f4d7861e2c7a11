// A long command's progress on stderr (see progress_line.hpp).
#include "progress_line.hpp"

#include <unistd.h>

#include <cstdio>

namespace nearcap::cli {

ProgressLine::ProgressLine(std::size_t steps) : steps_(steps), terminal_(::isatty(2) != 0) {}

ProgressLine::~ProgressLine() { end(); }

void ProgressLine::step(std::size_t done, const std::string& text) {
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
  char line[512];
  std::snprintf(line, sizeof line, "%s, %.0f s", text.c_str(), seconds);
  const std::string s = line;
  if (terminal_) {
    // Spaces over what a longer line before left.
    std::fprintf(stderr, "\r%s%*s", s.c_str(), width_ > s.size() ? static_cast<int>(width_ - s.size()) : 0, "");
    width_ = s.size();
    return;
  }
  if (done >= steps_ || (done - last_printed_) * 10 >= steps_) {
    std::fprintf(stderr, "%s\n", s.c_str());
    last_printed_ = done;
  }
}

void ProgressLine::end() {
  if (terminal_ && width_ > 0) std::fprintf(stderr, "\n");
  width_ = 0;
}

}  // namespace nearcap::cli
