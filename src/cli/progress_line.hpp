// cli/progress_line.hpp — a long command's progress on stderr.
//
// On a terminal one line, rewritten in place after every step; elsewhere (a
// log file, a pipe) a line of its own at each tenth of the steps and at the
// last, so that a log holds lines, not carriage returns.  `nearcap sweep`
// has its own (its rate and ETA, the ranks' configurations).
#pragma once

#include <chrono>
#include <cstddef>
#include <string>

namespace nearcap::cli {

class ProgressLine {
 public:
  // `steps`: how many steps the command takes (configurations, frames).
  explicit ProgressLine(std::size_t steps);
  // Ends a line left open on a terminal, so that what follows (an error)
  // starts a line of its own.
  ~ProgressLine();
  ProgressLine(const ProgressLine&) = delete;
  ProgressLine& operator=(const ProgressLine&) = delete;

  // Step `done` (1 to steps) finished; `text` says so ("calibrate:
  // configuration 3/320"), and the seconds since this line was made follow it.
  void step(std::size_t done, const std::string& text);
  // Ends the line on a terminal (nothing elsewhere).
  void end();

 private:
  std::size_t steps_;
  std::size_t last_printed_ = 0;  // the step of the last line printed (off a terminal)
  std::size_t width_ = 0;         // the length of the line on a terminal, 0 when none is open
  bool terminal_;
  std::chrono::steady_clock::time_point t0_ = std::chrono::steady_clock::now();
};

}  // namespace nearcap::cli
