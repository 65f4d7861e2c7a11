// The subcommands of the nearcap program, one file each.
#pragma once

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <optional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "nearcap/analysis/camera_path.hpp"
#include "nearcap/analysis/hard_case_sampler.hpp"
#include "nearcap/analysis/switch_policy.hpp"
#include "nearcap/error.hpp"
#include "nearcap/gl/shadow_methods.hpp"
#include "nearcap/io/output_files.hpp"
#include "nearcap/named_values.hpp"
#include "nearcap/scene/scene.hpp"

namespace nearcap::cli {

void register_classify(CLI::App& app);
void register_cap(CLI::App& app);
void register_reference(CLI::App& app);
void register_cracks(CLI::App& app);
void register_frame(CLI::App& app);
void register_sample(CLI::App& app);
void register_sweep(CLI::App& app);
void register_report(CLI::App& app);
void register_settings(CLI::App& app);
void register_tune(CLI::App& app);
void register_fit_l_near(CLI::App& app);
void register_render(CLI::App& app);     // builds with the real-GL library only (NEARCAP_WITH_RENDER)
void register_view(CLI::App& app);       // the same, with GLFW
void register_calibrate(CLI::App& app);  // the real-GL library too
void register_evaluate(CLI::App& app);   // the real-GL library too

// Where the files shipped with nearcap lie.  An installed program finds them
// beside itself, in <prefix>/share/nearcap (policy*.json, meshes/, scenes/,
// paths/, report/); a program with nothing installed beside it (the build
// tree's) reads the source tree it was built from (data/ and analysis/).
std::string shipped_data_dir();     // policy*.json, meshes/, scenes/, paths/
std::string shipped_scripts_dir();  // report/*.py

// The bundled camera path (data/paths/NAME.json) that `name`, NAME or
// NAME.json, names where no file of that name is here; "" otherwise.
std::string bundled_path_file(const std::string& name);
// A camera path file's path and its frames (analysis::load_camera_path).  A
// bundled path's name (bundled_path_file) is refused naming that file: only
// calibrate takes the bundled paths by name.
analysis::CameraPath load_camera_path_file(const std::string& file, MeshCache* meshes = nullptr);

// Thrown by a command whose child process already reported its error on
// stderr: main exits with this code and prints nothing more.
struct ExitCode {
  int code = 1;
};

// Thrown once a child process (Python) has ended after this one received
// `signal` (SIGINT, SIGTERM or SIGHUP) while waiting for it: the stack
// unwinds (temporary files removed), then main ends by that signal.
struct Interrupted {
  int signal = 0;
};

// The text of `j` (indent < 0: one line).  File names are bytes, and a
// string that is not UTF-8 has each bad byte written as U+FFFD rather than
// refused: the JSON names the file as well as JSON can, and the file itself
// keeps its real name.
std::string json_text(const nlohmann::json& j, int indent = -1);

// An output file option naming a directory: a one-line io error.
void refuse_directory(const std::string& file, const std::string& option);
// An output directory option naming something that is there and is not a
// directory: a one-line io error, before any work.
void refuse_non_directory(const std::string& dir, const std::string& option);

// "classify, cap, reference, cracks": the registered subcommands' names.
std::string subcommand_names(const CLI::App& app);

// A validator for an integer option: the value must be written in decimal
// digits and lie in [lo, hi] ("-5", "1e30", "0x10", "2.5" and a value past
// hi are usage errors naming the option and the range).  It runs on the text,
// before CLI11 converts it, so a negative value never wraps around to a huge
// unsigned one.  Give it with ->transform(), which lets it drop leading zeros
// (CLI11 reads "010" as octal); ->check() would keep them.
CLI::Validator integer_in(std::uint64_t lo, std::uint64_t hi);
// The largest viewport width or height in pixels (a scene file's limit too).
constexpr std::uint64_t kMaxViewportPixels = 16384;
// The most hard-case configurations one sweep or fit draws: each costs a few
// bytes of bookkeeping per rank up front, and a sweep this long already takes
// a cluster.
constexpr std::uint64_t kMaxSweepSamples = 100000000;
// The most configurations fit-l-near draws: it keeps every sampled scene in
// memory while Ceres fits.
constexpr std::uint64_t kMaxFitSamples = 100000;
// A validator for a floating-point option: a finite number ("inf", "nan" and
// "1e999" are usage errors).
CLI::Validator finite_number();

// Adds the --light option (required unless `required` is false): a
// non-negative integer written in digits ("-1", "1e0", "" and "abc" are usage
// errors naming the value).
CLI::Option* add_light_option(CLI::App& cmd, std::size_t& light, bool required = true);
// The same, not required: `given` says whether the command line gives it.
CLI::Option* add_optional_light_option(CLI::App& cmd, std::size_t& light, bool& given);

// `option`, with `given` set when the command line gives it.
CLI::Option* note_given(CLI::Option* option, bool& given);
// Throws Error(Usage) where --policy is given but nothing chosen reads it
// (`read_with` names the choice that would).
void refuse_unread_policy(bool given, bool read, const std::string& read_with);

// The SCENE argument: the scene file's path.
CLI::Option* add_scene_argument(CLI::App& cmd, std::string& scene);

// --max-memory GB, for the commands whose memory grows with the pixel count.
void add_max_memory_option(CLI::App& cmd, double& max_memory_gb);

// Refuses a frame whose estimated memory (fixed + per_pixel * width * height
// bytes) exceeds max_memory_gb (0: three quarters of the machine's memory),
// with the estimate in the message, before anything is allocated.
void check_memory_estimate(const Scene& scene, const std::string& command, double bytes_per_pixel,
                           double max_memory_gb);
// The same for a frame of width x height pixels from `source`; `advice`
// says what to lower ("lower --width/--height").  A command that keeps
// something of each of `configurations` frames to the end (calibrate's
// observations, evaluate's rows) adds bytes_per_configuration for each.
void check_memory_estimate(const std::string& source, int width, int height, const std::string& command,
                           double bytes_per_pixel, double max_memory_gb, const std::string& advice,
                           std::size_t configurations = 0, double bytes_per_configuration = 0);

// The float pipeline's choices, as command-line options (cracks, sweep, ...).
// The options set the fields of gl::EmulationSettings itself, so each
// default is the pipeline's own; a named choice holds its enum, parsed once
// where the command line is read, by the name table next to the enum
// (nearcap/named_values.hpp).  Two choices read differently on the command
// line and are held in their command-line form: settings_from turns them
// into settings.raster.mesa_clipper and settings.arithmetic, whose values in
// `settings` are not read.
struct EmulationOptions {
  gl::EmulationSettings settings;
  gl::ClipperArithmetic clipper = gl::ClipperArithmetic::Inside;  // --clipper
  bool fma = false;                                               // --fma
};
void add_emulation_options(CLI::App& cmd, EmulationOptions& options);
// Only the emulation options named in `names` (without their dashes), for a
// command that reads no others (the rest are then unknown options).
void add_emulation_options(CLI::App& cmd, EmulationOptions& options, const std::vector<std::string>& names);
// `base` with the choices of a variant spec "NAME=VALUE[,NAME=VALUE...]"
// overridden (NAME: an emulation option without its dashes, e.g.
// "light-projection=glfrustum,l-near-scale=0.5"; fma=1 or fma=0).  Throws
// Error(Usage) naming an unknown name or a bad value.
EmulationOptions with_variant(const EmulationOptions& base, const std::string& spec);
// The choices that differ from the defaults, as a variant spec; "default" when none.
std::string variant_label(const EmulationOptions& options);
// Every emulation option by name (without its dashes) and value, as text, in
// a fixed order (the sweep's header and variant labels): the order of
// visit_emulation_options.
std::vector<std::pair<std::string, std::string>> emulation_option_values(const EmulationOptions& options);
// Throws Error(Usage) for a value out of range.
gl::EmulationSettings settings_from(const EmulationOptions& options);
// The emulation options that are named choices, in that order, as JSON:
// [{"option": NAME, "help": ..., "values": [{"name", "help"}, ...]}, ...].
nlohmann::json emulation_choices_json();

// The settings tables as one JSON document (`nearcap settings`; the report
// script reads it): format "nearcap-settings", version
// kSettingsTableVersion, "methods" (the values of a sweep row's method
// column in the report's order, each with its label, kind and roles),
// "kinds" (the sampler's) and "choices" (emulation_choices_json).
inline constexpr int kSettingsTableVersion = 1;
nlohmann::json settings_table_json();

// A new empty file in the temporary directory, named PREFIX + 6 random
// characters + SUFFIX; empty when none could be made (errno says why).
std::string temporary_file(const std::string& prefix, const std::string& suffix);

// The settings table (settings_table_json) in a temporary file, for a
// script's --settings; removed with this object.  Throws Error(Io) when it
// cannot be written.
class SettingsFile {
 public:
  SettingsFile();
  SettingsFile(const SettingsFile&) = delete;
  SettingsFile& operator=(const SettingsFile&) = delete;
  ~SettingsFile();
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

// --samples N, how many configurations the hard-case sampler draws: a whole
// number in [lo, hi]; `help` says what they are for.
CLI::Option* add_samples_option(CLI::App& cmd, std::uint64_t& samples, const std::string& help, std::uint64_t lo,
                                std::uint64_t hi);
// --width and --height, the viewport of every configuration in pixels (1 to
// kMaxViewportPixels).  `width_default` and `height_default` are what the
// help says of the defaults (" (default: ...)"); empty, it shows the values
// the options start with.
void add_viewport_options(CLI::App& cmd, int& width, int& height, const std::string& width_default = "",
                          const std::string& height_default = "");

// The hard-case sampler's options (sample, sweep, fit-l-near).
struct SamplerOptions {
  std::uint64_t seed = 1;
  std::string kinds = "all";
  int width = 48, height = 36;
  bool allow_bunny = false;
  std::string given;  // the first of --seed, --kinds, --allow-bunny on the command line, or ""
};

analysis::SamplerSpec sampler_spec(const SamplerOptions& o);

// The --path files of a command that names its rows or pictures by them
// (sweep, calibrate, evaluate: "path:NAME:FRAME", NAME the file's stem):
// Error(Usage) for a file given twice, two files of one name, or a file
// name that is not UTF-8 text or holds a control character (it goes into
// CSV fields and a row's replay command).
void check_camera_path_names(const std::vector<std::string>& paths);
// The configurations a command leaves out because they do not load (a
// sampled light inside an occluder, say; `nearcap sweep` writes each as a
// rejected row): how many, and the first with its reason, for the
// command's summary.  All of them left out is an error: nothing was measured.
class RejectedConfigurations {
 public:
  void add(const std::string& id, const Error& e);
  std::size_t count() const { return count_; }
  // "2 configurations rejected (they do not load; the first, ID: REASON)".
  std::string sentence() const;
  // Error, of the first's kind, when every one of `total` (> 0) was rejected.
  void refuse_all_rejected(std::size_t total) const;

 private:
  std::size_t count_ = 0;
  std::string first_id_, first_reason_;
  ErrorKind first_kind_ = ErrorKind::Io;
};

// Where NEARCAP_DATA_DIR is set, its meshes folder must hold the sampler's
// meshes, each loading as an occluder: Error naming the folder and the file
// otherwise (Io where one is missing, the reading's kind where one is
// broken; every configuration naming it would be rejected).  For the
// commands that sample (--samples above 0).
void check_sampler_meshes(const analysis::SamplerSpec& spec);
// Error(Usage) where a sampler option is given to a command that samples
// nothing (`samples` 0: camera paths alone), rather than ignored.
void refuse_unread_sampler_options(const SamplerOptions& o, std::uint64_t samples);
// `sizes`: the --width and --height options too.
void add_sampler_options(CLI::App& cmd, SamplerOptions& o, bool sizes);
// The names of a comma-separated list, in order, empty ones kept: "" is one
// empty name, "a,,b" three (the caller's name table refuses them).
std::vector<std::string> comma_separated(const std::string& names);
// Error(Usage) when `name`, one name of `option`'s list, is a word that
// stands for a whole list (`all`, `none`) and must be given alone.
void refuse_list_word(const std::string& option, const std::string& name,
                      std::initializer_list<const char*> words = {"all"});
// The methods named by --method/--methods: one name, a comma-separated list,
// or "all".  Throws Error(Usage) naming an unknown one.
std::vector<gl::ShadowMethod> methods_from(const std::string& names, const std::string& option);
// --method of cracks and render: the stencil methods, and two names that are
// not one: "policy" (the switch policy, a method per occluder) and
// "raytrace" (Embree).  "all" is every stencil method, the policy and
// raytrace.
struct MethodChoice {
  std::vector<gl::ShadowMethod> methods;
  bool raytrace = false;
  bool policy = false;
  std::size_t count() const { return methods.size() + (raytrace ? 1 : 0) + (policy ? 1 : 0); }
};
// `lists_raytrace`: false where the command refuses the ray tracer (the
// real-GL commands), so that an unknown name's message leaves it out.
MethodChoice method_choice(const std::string& names, bool lists_raytrace = true);
// The policy's method per occluder and why, as a JSON array of
// {"object", "method", "why"}.
nlohmann::json policy_occluders_json(const Scene& scene, const analysis::PolicyDecision& d);
// An option whose value is one of E's names (named_values.hpp): the help is
// `help`, the accepted values and the default are the table's (CLI11 lists
// them), and the option stores the value, not the name.
template <class E>
CLI::Option* add_choice_option(CLI::App& cmd, const std::string& flag, E& value, const std::string& help) {
  return cmd
      .add_option_function<std::string>(
          flag, [&value](const std::string& name) { value = *value_named<E>(name); }, help)
      ->check(CLI::IsMember(names_of<E>()))
      ->default_str(std::string(name_of(value)));
}
// The same for a choice with no default: nullopt when the option is not given.
template <class E>
CLI::Option* add_choice_option(CLI::App& cmd, const std::string& flag, std::optional<E>& value,
                               const std::string& help) {
  return cmd
      .add_option_function<std::string>(
          flag, [&value](const std::string& name) { value = value_named<E>(name); }, help)
      ->check(CLI::IsMember(names_of<E>()));
}

// What the cases A, B, C1, C2, D and degenerate mean (ZP+ section 5), a line each.
void print_case_legend(std::ostream& out);

// Throws Error(Usage) when `light` is not an index of scene.lights.
void check_light_index(const Scene& scene, std::size_t light);

// Runs `python script args...` with the Python that has matplotlib
// (NEARCAP_PYTHON, else /usr/bin/python3, Debian's, else python3 on the
// PATH), its stderr written to the open file `stderr_fd`, and returns
// waitpid's raw status (the caller tells an exit from a signal); `what`
// names the script in the error when Python cannot be started (Error(Io),
// naming the packages to install).  output_script.hpp runs the shipped
// scripts through it.
int run_python_script_logged(const std::string& script, const std::vector<std::string>& args, const std::string& what,
                             int stderr_fd);

}  // namespace nearcap::cli
