// How a nearcap subcommand joins the program: its option values in one
// Options struct, owned with the subcommand (each option is bound to a field
// of it), and the function that runs the command on them once the command
// line is parsed.
#pragma once

#include <CLI/CLI.hpp>

#include <memory>
#include <string>

namespace nearcap::cli {

template <class Options>
struct Subcommand {
  CLI::App& cmd;     // to add the options to
  Options& options;  // the values they are bound to, handed to run
};

// Adds subcommand `name` with its one-line `help` to `app`, its options'
// values a default Options; run(options) runs it after parsing (what it
// throws is main's to report).
template <class Options, class Run>
Subcommand<Options> add_subcommand(CLI::App& app, const std::string& name, const std::string& help, Run run) {
  auto options = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(name, help);
  cmd->callback([options, run] { run(*options); });
  return {*cmd, *options};
}

}  // namespace nearcap::cli
