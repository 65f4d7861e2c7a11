// nearcap — command-line front end.  Each subcommand loads and validates a
// scene, computes everything, and only then writes its output, so a failure
// leaves no partial files behind.  Errors: one line on stderr,
// "nearcap: error (KIND): ...", naming the file, the element and the fault;
// exit code 2 for bad input and bad usage, 1 for internal faults.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <new>
#include <string>

#include "cli_commands.hpp"
#include "mpi_world.hpp"
#include "nearcap/error.hpp"
#include "nearcap/io/utf8_text.hpp"

namespace {

constexpr const char* kVersion = "nearcap " NEARCAP_VERSION;  // the project version, CMakeLists.txt

int usage_error(const std::string& message) {
  if (const nearcap::cli::MpiWorld* world = nearcap::cli::mpi_world(); world && world->rank() != 0) return 2;
  // CLI11 breaks its messages over lines: joined with spaces.
  std::string line = message;
  std::replace(line.begin(), line.end(), '\n', ' ');
  while (!line.empty() && line.back() == ' ') line.pop_back();
  std::fprintf(stderr, "nearcap: error (usage): %s (see nearcap --help)\n",
               nearcap::io::escaped_control_characters(line).c_str());
  return 2;
}

// Whether everything printed on stdout was written (a full disk or a closed
// stdout is not); else reports it (on rank 0) and returns false.
bool stdout_written(bool report) {
  // A write that failed before (help text is written through std::cout)
  // left its reason in errno; the flush's own failure, if any, comes after.
  const int earlier = std::ferror(stdout) != 0 || !std::cout.good() ? errno : 0;
  errno = 0;
  const bool flushed = std::fflush(stdout) == 0;
  if (flushed && std::cout.good() && std::ferror(stdout) == 0) return true;
  const int err = errno != 0 ? errno : earlier;
  if (report)
    std::fprintf(stderr, "nearcap: error (io): standard output: cannot write what the command printed%s%s\n",
                 err != 0 ? ": " : "", err != 0 ? std::strerror(err) : "");
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  nearcap::cli::MpiWorld world(&argc, &argv);
  // Under MPI: a failure once the ranks work apart ends them all; before,
  // every rank meets the same error and rank 0 alone reports it.
  const auto fail = [&world](int code) {
    if (world.size() > 1 && world.sharded()) world.abort(code);
    return code;
  };
  const auto report = [&world] { return world.rank() == 0 || world.sharded(); };
  CLI::App app{"nearcap: exact and float analysis of stencil shadow volumes (ZP+)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", kVersion, "print the version and exit");
  nearcap::cli::register_classify(app);
  nearcap::cli::register_cap(app);
  nearcap::cli::register_reference(app);
  nearcap::cli::register_cracks(app);
  nearcap::cli::register_frame(app);
  nearcap::cli::register_sample(app);
  nearcap::cli::register_sweep(app);
  nearcap::cli::register_report(app);
  nearcap::cli::register_settings(app);
  nearcap::cli::register_tune(app);
  nearcap::cli::register_fit_l_near(app);
#ifdef NEARCAP_WITH_RENDER
  nearcap::cli::register_render(app);
  nearcap::cli::register_view(app);
  nearcap::cli::register_calibrate(app);
  nearcap::cli::register_evaluate(app);
#endif

  // `nearcap` alone, `nearcap help` and `nearcap --help` print the help;
  // `nearcap help CMD` and `nearcap --help CMD`, CMD's.
  const bool help_first = argc >= 2 && (std::strcmp(argv[1], "help") == 0 || std::strcmp(argv[1], "--help") == 0 ||
                                        std::strcmp(argv[1], "-h") == 0);
  if (argc < 2 || help_first) {
    app.name("nearcap");  // parse() would name it after argv[0]
    const CLI::App* topic = &app;
    if (argc > 3)
      return usage_error(std::string(argv[1]) + " takes one subcommand's name (found '" + argv[3] + "' after '" +
                         argv[2] + "')");
    if (argc > 2) {
      const auto all = app.get_subcommands([](const CLI::App*) { return true; });
      const auto sub =
          std::find_if(all.begin(), all.end(), [&](const CLI::App* s) { return s->get_name() == argv[2]; });
      if (sub == all.end())
        return usage_error(std::string("no help on '") + argv[2] + "' (one of " + nearcap::cli::subcommand_names(app) +
                           ")");
      topic = *sub;
    }
    if (world.rank() == 0) std::fputs(topic->help().c_str(), stdout);
    return stdout_written(world.rank() == 0) ? 0 : 2;
  }
  // The subcommand comes first; name an unknown one as such.
  const auto subcommands = app.get_subcommands([](const CLI::App*) { return true; });
  if (argv[1][0] != '-' && std::none_of(subcommands.begin(), subcommands.end(),
                                        [&](const CLI::App* sub) { return sub->get_name() == argv[1]; }))
    return usage_error(std::string("unknown subcommand '") + argv[1] + "' (one of " +
                       nearcap::cli::subcommand_names(app) + ")");
  if (argv[1][0] == '-' && std::strcmp(argv[1], "--version") != 0)
    return usage_error(std::string("unknown option '") + argv[1] + "': the subcommand comes first (one of " +
                       nearcap::cli::subcommand_names(app) + ")");
  if (std::strcmp(argv[1], "--version") == 0 && argc > 2)
    return usage_error(std::string("--version takes no arguments (found '") + argv[2] + "')");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) {  // --help, --version
      app.exit(e);
      return stdout_written(world.rank() == 0) ? 0 : 2;
    }
    if (dynamic_cast<const CLI::RequiredError*>(&e) != nullptr && app.get_subcommands().empty())
      return usage_error("no subcommand given (one of " + nearcap::cli::subcommand_names(app) + ")");
    // CLI11's words for an option given more than once.
    const std::string what = e.what();
    const std::size_t at_most = what.find(": At Most 1 required but received ");
    if (dynamic_cast<const CLI::ArgumentMismatch*>(&e) != nullptr && at_most != std::string::npos)
      return usage_error(what.substr(0, at_most) + " is given " +
                         what.substr(at_most + std::strlen(": At Most 1 required but received ")) +
                         " times (give it once)");
    // CLI11 lists the extras of a subcommand last first: in the order given.
    if (dynamic_cast<const CLI::ExtrasError*>(&e) != nullptr) {
      const std::vector<std::string> extras = app.remaining(true);
      if (!extras.empty()) {
        std::string list;
        for (const std::string& a : extras) list += (list.empty() ? "" : " ") + a;
        return usage_error((extras.size() > 1 ? "unexpected arguments: " : "unexpected argument: ") + list);
      }
    }
    return usage_error(what);
  } catch (const nearcap::cli::ExitCode& e) {
    return fail(e.code);
  } catch (const nearcap::cli::Interrupted& e) {
    // Ended by the signal, as it would have been without a child to wait for.
    std::signal(e.signal, SIG_DFL);
    std::raise(e.signal);
    return 128 + e.signal;
  } catch (const nearcap::Error& e) {
    if (report())
      std::fprintf(stderr, "nearcap: error (%s): %s\n", std::string(nearcap::to_string(e.kind())).c_str(),
                   nearcap::io::escaped_control_characters(e.what()).c_str());
    return fail(2);
  } catch (const std::bad_alloc&) {
    if (report())
      std::fprintf(stderr,
                   "nearcap: error (resource): out of memory (a frame's width and height, or an input file, too "
                   "large for this machine's memory; see docs/scene-format.md, \"Limits on inputs\")\n");
    return fail(2);
  } catch (const std::exception& e) {
    if (report())
      std::fprintf(stderr, "nearcap: internal error: %s\n", nearcap::io::escaped_control_characters(e.what()).c_str());
    return fail(1);
  }
  // What the command printed on stdout, all of it written: a full disk or a
  // closed stdout fails the command instead of leaving a short output behind
  // a success.
  if (!stdout_written(report())) return fail(2);
  return 0;
}
