// How a nearcap subcommand joins the program: its option values in one
// Options struct, owned with the subcommand (each option is bound to a field
// of it), and the function that runs the command on them once the command
// line is parsed.
#pragma once

#include <CLI/CLI.hpp>

#include <memory>
#include <string>

#include "nearcap/error.hpp"

namespace nearcap::cli {

template <class Options>
struct Subcommand {
  CLI::App& cmd;     // to add the options to
  Options& options;  // the values they are bound to, handed to run
};

// Adds subcommand `name` with its one-line `help` to `app`, its options'
// values a default Options; run(options) runs it after parsing (what it
// throws is main's to report).
// A file-naming option given an empty value (`--out ""`) is refused: an
// empty name would read as the option left out (stdout, the default).
inline void refuse_empty_file_names(const CLI::App& cmd) {
  for (const CLI::Option* o : cmd.get_options()) {
    const std::string& name = o->get_name();
    if (name != "--out" && name != "--svg" && name != "--screenshot" && name != "--policy" && name != "--path" &&
        name != "--write-policy" && name != "--fit-unpriced")
      continue;
    for (const std::string& value : o->results())
      if (value.empty()) throw Error(ErrorKind::Usage, name + ": the file name is empty");
  }
}

// A flag given more than once is refused as an option given twice is
// (CLI11 counts a flag's uses and goes on).
inline void refuse_repeated_flags(const CLI::App& cmd) {
  for (const CLI::Option* o : cmd.get_options())
    if (o->get_expected_max() == 0 && o->count() > 1)  // a flag: no value
      throw Error(ErrorKind::Usage,
                  o->get_name() + " is given " + std::to_string(o->count()) + " times (give it once)");
}

template <class Options, class Run>
Subcommand<Options> add_subcommand(CLI::App& app, const std::string& name, const std::string& help, Run run) {
  auto options = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(name, help);
  cmd->callback([cmd, options, run] {
    refuse_empty_file_names(*cmd);
    refuse_repeated_flags(*cmd);
    run(*options);
  });
  return {*cmd, *options};
}

}  // namespace nearcap::cli
