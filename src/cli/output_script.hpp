// cli/output_script.hpp — running one of the shipped Python scripts that
// write a file (the sweep report's page, evaluate's and render --bench's
// plots) so that whatever happens to the script, the command ends with one
// line: the script's own "nearcap: error (KIND): ..." line, or one naming
// the script, how it ended and where its output went; and so that a script
// that exits 0 without writing its file is an error, not a success.
#pragma once

#include <string>
#include <vector>

namespace nearcap::cli {

// Error(Io) unless `script` is a readable regular file; `what` names it
// ("the report script").
void check_script_file(const std::string& script, const std::string& what);

// Runs `python script args...` (run_python_script_logged's Python), its
// stderr in a log file of the temporary directory (an anonymous file in
// memory where that takes none).  Exit 0: `output` must have been written
// by this run (Error(Io) naming it otherwise), then what the script wrote on
// stderr (its warnings) is forwarded.  Exit 2 with a last line
// "nearcap: error (KIND): ...": that line on stderr (with the log's name
// when the script wrote more), then ExitCode{2}.  Anything else:
// Error(Io) naming the script, its status or signal, and the log (or, in
// memory, its last line).
void run_output_script(const std::string& script, const std::vector<std::string>& args, const std::string& what,
                       const std::string& output);

// Runs `python script --check`: the script's imports (matplotlib) are
// there, before a long run whose last step is the script.  Its failure
// as run_output_script's.
void check_output_script(const std::string& script, const std::string& what);

}  // namespace nearcap::cli
