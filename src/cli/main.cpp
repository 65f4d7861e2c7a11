// nearcap — command-line front end.  Each subcommand loads and validates a
// scene, computes everything, and only then writes its output, so a failure
// leaves no partial files behind.  Errors: one line on stderr,
// "nearcap: error (KIND): ...", naming the file, the element and the fault;
// exit code 2 for bad input and bad usage, 1 for internal faults.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <new>
#include <string>
#include <vector>

#include "cli_commands.hpp"
#include "mpi_world.hpp"
#include "nearcap/error.hpp"
#include "nearcap/io/utf8_text.hpp"

namespace {

constexpr const char* kVersion = "nearcap " NEARCAP_VERSION;  // the project version, CMakeLists.txt

// `help`: the page that explains it ("nearcap cap --help" where a
// subcommand was named).
int usage_error(const std::string& message, const std::string& help = "nearcap --help") {
  if (const nearcap::cli::MpiWorld* world = nearcap::cli::mpi_world(); world && world->rank() != 0) return 2;
  // CLI11 breaks its messages over lines: joined with spaces.
  std::string line = message;
  std::replace(line.begin(), line.end(), '\n', ' ');
  while (!line.empty() && line.back() == ' ') line.pop_back();
  std::fprintf(stderr, "nearcap: error (usage): %s (see %s)\n", nearcap::io::escaped_control_characters(line).c_str(),
               help.c_str());
  return 2;
}

// Whether a command-line word is an option's name (--name, --name=value,
// -x), not a value: "-1" and "-0.5" are values.
bool names_an_option(const std::string& word) {
  return word.size() >= 2 && word[0] == '-' && (word[1] == '-' || std::isalpha(static_cast<unsigned char>(word[1])));
}

// Levenshtein distance (insertions, deletions, substitutions).
std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

// Whether `given` (--name or -x) names one of `command`'s options.
bool is_option_of(const CLI::App& command, const std::string& given) {
  for (const CLI::Option* option : command.get_options()) {
    for (const std::string& name : option->get_lnames())
      if (given == "--" + name) return true;
    for (const std::string& name : option->get_snames())
      if (given == "-" + name) return true;
  }
  return false;
}

// Whether `message` names one of `command`'s long options (--name, not
// inside a longer word): what its help page explains.
bool names_an_option_of(const CLI::App& command, const std::string& message) {
  auto name_character = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '-'; };
  for (std::size_t at = message.find("--"); at != std::string::npos; at = message.find("--", at + 2)) {
    if (at > 0 && name_character(message[at - 1])) continue;
    std::size_t end = at + 2;
    while (end < message.size() && name_character(message[end])) ++end;
    if (is_option_of(command, message.substr(at, end - at))) return true;
  }
  return false;
}

// `command`'s long option nearest to `given` (--ligth: --light), where one
// is within two edits and nearer than any other; "" otherwise.
std::string nearest_option(const CLI::App& command, const std::string& given) {
  std::string best;
  std::size_t best_distance = 3;
  bool tied = false;
  for (const CLI::Option* option : command.get_options())
    for (const std::string& name : option->get_lnames()) {
      const std::size_t d = edit_distance(given, "--" + name);
      if (d < best_distance) {
        best = "--" + name;
        best_distance = d;
        tied = false;
      } else if (d == best_distance) {
        tied = true;
      }
    }
  return tied ? "" : best;
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
    // A subcommand's usage line under the program's name, "nearcap CMD"
    // (`CMD --help` names it as it was run, argv[0]).
    if (world.rank() == 0) std::fputs(topic->help(topic == &app ? "" : "nearcap").c_str(), stdout);
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
    const std::vector<CLI::App*> named = app.get_subcommands();
    const std::string help = named.empty() ? "nearcap --help" : "nearcap " + named.front()->get_name() + " --help";
    // An option the subcommand does not have is named first: it is often why
    // another seems missing (--ligth 0 for --light 0).
    if (!named.empty())
      for (const std::string& word : app.remaining(true)) {
        if (word == "--") break;  // what follows was given as positionals
        const std::string given = word.substr(0, word.find('='));
        if (!names_an_option(word) || is_option_of(*named.front(), given)) continue;
        const std::string nearest = nearest_option(*named.front(), given);
        return usage_error(
            "unknown option '" + given + "'" + (nearest.empty() ? "" : " (did you mean " + nearest + "?)"), help);
      }
    // CLI11's words for an option given more than once.
    const std::string what = e.what();
    const std::size_t at_most = what.find(": At Most 1 required but received ");
    if (dynamic_cast<const CLI::ArgumentMismatch*>(&e) != nullptr && at_most != std::string::npos)
      return usage_error(what.substr(0, at_most) + " is given " +
                             what.substr(at_most + std::strlen(": At Most 1 required but received ")) +
                             " times (give it once)",
                         help);
    // CLI11 lists the extras of a subcommand last first: in the order given.
    if (dynamic_cast<const CLI::ExtrasError*>(&e) != nullptr) {
      const std::vector<std::string> extras = app.remaining(true);
      if (!extras.empty()) {
        std::string list;
        for (const std::string& a : extras) list += (list.empty() ? "" : " ") + a;
        return usage_error((extras.size() > 1 ? "unexpected arguments: " : "unexpected argument: ") + list, help);
      }
    }
    return usage_error(what, help);
  } catch (const nearcap::cli::ExitCode& e) {
    return fail(e.code);
  } catch (const nearcap::cli::Interrupted& e) {
    // Ended by the signal, as it would have been without a child to wait for.
    std::signal(e.signal, SIG_DFL);
    std::raise(e.signal);
    return 128 + e.signal;
  } catch (const nearcap::Error& e) {
    // A usage mistake the command finds in its options names their help
    // page, as CLI11's do (not one in an input's content or the
    // environment, which that page does not explain).
    const std::vector<CLI::App*> named = app.get_subcommands();
    const std::string help =
        e.kind() == nearcap::ErrorKind::Usage && !named.empty() && names_an_option_of(*named.front(), e.what())
            ? " (see nearcap " + named.front()->get_name() + " --help)"
            : "";
    if (report())
      std::fprintf(stderr, "nearcap: error (%s): %s%s\n", std::string(nearcap::to_string(e.kind())).c_str(),
                   nearcap::io::escaped_control_characters(e.what()).c_str(), help.c_str());
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
