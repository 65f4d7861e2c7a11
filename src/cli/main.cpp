// nearcap — command-line front end.  Each subcommand loads and validates a
// scene, computes everything, and only then writes its output, so a failure
// leaves no partial files behind.  Errors: one line on stderr naming the file,
// the element and the fault; exit code 2 for bad input, 1 for internal faults.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <iostream>

#include "cli_commands.hpp"
#include "nearcap/error.hpp"

int main(int argc, char** argv) {
  CLI::App app{"nearcap: exact and float analysis of stencil shadow volumes (ZP+)"};
  app.require_subcommand(1);
  nearcap::cli::register_classify(app);
  nearcap::cli::register_cap(app);
  nearcap::cli::register_reference(app);
  nearcap::cli::register_cracks(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const nearcap::Error& e) {
    std::fprintf(stderr, "nearcap: error (%s): %s\n", std::string(nearcap::to_string(e.kind())).c_str(), e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "nearcap: internal error: %s\n", e.what());
    return 1;
  }
  return 0;
}
