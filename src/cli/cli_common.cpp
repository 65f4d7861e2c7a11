#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <initializer_list>
#include <limits>
#include <set>
#include <sstream>
#include <type_traits>
#include <utility>

#include "cli_commands.hpp"
#include "nearcap/check.hpp"
#include "nearcap/error.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/io/utf8_text.hpp"

extern char** environ;

namespace nearcap::cli {

void refuse_directory(const std::string& file, const std::string& option) {
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec))
    throw Error(ErrorKind::Io, option + " '" + file + "' is a directory, not a file");
}

void refuse_non_directory(const std::string& dir, const std::string& option) {
  std::error_code ec;
  const std::filesystem::file_status st = std::filesystem::status(dir, ec);
  if (!ec && std::filesystem::exists(st) && !std::filesystem::is_directory(st))
    throw Error(ErrorKind::Io, option + " '" + dir + "' is there and is not a directory");
  if (ec == std::errc::not_a_directory)
    throw Error(ErrorKind::Io, option + " '" + dir + "': a folder on its way is a file, not a directory");
}

std::string json_text(const nlohmann::json& j, int indent) {
  return j.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace);
}

std::string subcommand_names(const CLI::App& app) {
  std::string names;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
    names += (names.empty() ? "" : ", ") + sub->get_name();
  return names;
}

CLI::Validator integer_in(std::uint64_t lo, std::uint64_t hi) {
  const std::string range = "[" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  return CLI::Validator(
      [lo, hi, range](std::string& value) -> std::string {
        const std::string quoted = "'" + value + "'";
        if (!value.empty() && value[0] == '-' && value.size() > 1 &&
            std::all_of(value.begin() + 1, value.end(), [](char c) { return c >= '0' && c <= '9'; }))
          return quoted + " is negative (expected a whole number in " + range + ")";
        if (value.empty() || !std::all_of(value.begin(), value.end(), [](char c) { return c >= '0' && c <= '9'; }))
          return quoted + " is not a whole number in decimal digits (expected one in " + range + ")";
        const std::size_t first = std::min(value.find_first_not_of('0'), value.size() - 1);
        const std::string digits = value.substr(first);
        // 2^64 - 1 has 20 digits: compare as text so that nothing overflows.
        const std::string max = std::to_string(hi);
        if (digits.size() > max.size() || (digits.size() == max.size() && digits > max) || std::stoull(digits) < lo)
          return quoted + " is out of range (expected a whole number in " + range + ")";
        value = digits;
        return std::string();
      },
      "INTEGER in " + range);
}

CLI::Validator finite_number() {
  return CLI::Validator(
      [](std::string& value) -> std::string {
        char* end = nullptr;
        const double d = std::strtod(value.c_str(), &end);
        // A value below the doubles' range (ERANGE, rounded to a subnormal or
        // zero) is finite; one above it is infinite.
        const bool ok = !value.empty() && end == value.c_str() + value.size() && std::isfinite(d);
        return ok ? std::string() : "'" + value + "' is not a finite number";
      },
      "FINITE");
}

CLI::Option* add_light_option(CLI::App& cmd, std::size_t& light, bool required) {
  const CLI::Validator digits(
      [](std::string& value) -> std::string {
        const bool digits_only =
            !value.empty() && std::all_of(value.begin(), value.end(), [](char c) { return c >= '0' && c <= '9'; });
        if (!digits_only) return "'" + value + "' is not a light index (a non-negative integer)";
        // Leading zeros are no part of the value (010 is light 10, not
        // CLI11's octal 8).
        const std::string significant = value.substr(std::min(value.find_first_not_of('0'), value.size() - 1));
        if (significant.size() > 9) return "'" + value + "' is far above any scene's number of lights";
        value = significant;
        return std::string();
      },
      "INDEX");
  CLI::Option* option = cmd.add_option("--light", light, "index of the light in the scene's list (0, 1, ...)");
  option->required(required)->transform(digits);
  return option;
}

CLI::Option* add_optional_light_option(CLI::App& cmd, std::size_t& light, bool& given) {
  return note_given(add_light_option(cmd, light, false), given);
}

CLI::Option* note_given(CLI::Option* option, bool& given) {
  return option->each([&given](const std::string&) { given = true; });
}

void refuse_unread_policy(bool given, bool read, const std::string& read_with) {
  if (given && !read)
    throw Error(ErrorKind::Usage, "--policy is read only with " + read_with + ": no method chosen uses it");
}

CLI::Option* add_scene_argument(CLI::App& cmd, std::string& scene) {
  return cmd.add_option("scene", scene, "scene file (JSON)");
}

void add_max_memory_option(CLI::App& cmd, double& max_memory_gb) {
  cmd.add_option("--max-memory", max_memory_gb,
                 "refuse a run whose estimated memory (its largest frame's; for calibrate and evaluate also what each "
                 "configuration keeps to the end) exceeds this many GB (default: 3/4 of the machine's memory)")
      ->check(finite_number())
      ->check(CLI::Validator(
          [](std::string& value) -> std::string {
            return std::strtod(value.c_str(), nullptr) > 0 ? std::string() : "'" + value + "' is not above 0 (GB)";
          },
          "POSITIVE"));
}

void check_memory_estimate(const Scene& scene, const std::string& command, double bytes_per_pixel,
                           double max_memory_gb) {
  check_memory_estimate(scene.source, scene.camera.width, scene.camera.height, command, bytes_per_pixel, max_memory_gb,
                        "lower width/height in the scene");
}

void check_memory_estimate(const std::string& source, int width, int height, const std::string& command,
                           double bytes_per_pixel, double max_memory_gb, const std::string& advice,
                           std::size_t configurations, double bytes_per_configuration) {
  const double pixels = static_cast<double>(width) * height;
  const double kept = bytes_per_configuration * static_cast<double>(configurations);
  const double estimate = 64e6 + bytes_per_pixel * pixels + kept;
  double limit = max_memory_gb * 1e9;
  if (limit <= 0) {
    const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
    limit = pages > 0 && page > 0 ? 0.75 * static_cast<double>(pages) * static_cast<double>(page) : 8e9;
  }
  if (estimate <= limit) return;
  char kept_part[160] = "";
  if (configurations > 0)
    std::snprintf(kept_part, sizeof kept_part, " and %.0f KB for each of %zu configuration%s",
                  bytes_per_configuration / 1e3, configurations, configurations == 1 ? "" : "s");
  char message[800];
  std::snprintf(message, sizeof message,
                "%s: %s at %dx%d needs about %.3g GB (%.0f bytes per pixel%s), over the limit of %.3g GB; %s, or "
                "raise the limit with --max-memory GB",
                source.c_str(), command.c_str(), width, height, estimate / 1e9, bytes_per_pixel, kept_part, limit / 1e9,
                advice.c_str());
  throw Error(ErrorKind::Resource, message);
}

namespace {

// One emulation option: its name on the command line (without the dashes)
// and in a variant spec, and its help.  A named choice's help is
// "LEAD: the table's values and descriptions TAIL".
struct EmulationOption {
  const char* name;
  const char* lead;
  const char* tail = "";
};

// Calls visit(option, field) for every emulation option, in the order of the
// sweep's header and of variant labels (files written by earlier sweeps hold
// it, and a resumed sweep compares it).
template <class Options, class Visit>
void visit_emulation_options(Options& o, Visit&& visit) {
  auto& s = o.settings;
  visit(EmulationOption{"subpixel-bits", "fixed-point sub-pixel bits of the rasterizer"}, s.raster.subpixel_bits);
  visit(EmulationOption{"depth", "depth buffer"}, s.depth);
  visit(EmulationOption{"fill-rule", "pixel centres on an edge"}, s.raster.fill_rule);
  visit(EmulationOption{"guard-band",
                        "x/y clipping at |x|,|y| <= G w: 1 is llvmpipe's view-volume clip, larger a GPU-style guard "
                        "band"},
        s.raster.guard_band);
  visit(EmulationOption{"viewport", "perspective divide and viewport arithmetic"}, s.raster.viewport);
  visit(EmulationOption{"depth-interpolation", "a fragment's depth"}, s.raster.depth);
  visit(EmulationOption{"clipper", "the clipper's arithmetic",
                        "; --viewport llvmpipe --depth-interpolation llvmpipe --clipper mesa is the llvmpipe model"},
        o.clipper);
  visit(EmulationOption{"light-projection", "P_l formulation"}, s.light_frustum.projection);
  visit(EmulationOption{"l-near", "how ZP+'s light frustum picks l_near"}, s.light_frustum.near_rule);
  visit(EmulationOption{"l-near-scale", "l_near multiplied by this safety margin in (0, 1]"},
        s.light_frustum.near_scale);
  visit(EmulationOption{"zfail-far", "zfail's far plane"}, s.zfail_far);
  visit(EmulationOption{"switch-clamp", "depth clamp of ZP+'s switch to zfail (case D, no light frustum)"},
        s.switch_clamp);
  visit(EmulationOption{"zpass-far", "zpass's projection"}, s.zpass_far);
  visit(EmulationOption{"infinite-far", "the infinite projection's depth row"}, s.infinite_far);
  visit(EmulationOption{"fma",
                        "vertex transforms with fused multiply-add (a GPU that fuses; llvmpipe's GLSL fma() does "
                        "not)"},
        o.fma);
  visit(EmulationOption{"depth-mapping", "the camera's depth"}, s.depth_mapping);
  visit(EmulationOption{"near-plane", "the camera's near plane"}, s.near_plane);
  visit(EmulationOption{"volume-culling", "each occluder's draws limited to where its volume can change a pixel",
                        "; the same stencil, fewer fragments"},
        s.volume_culling);
}

template <class T>
constexpr bool kIsChoice = std::is_enum_v<T>;

// `v` as a variant label writes it: six significant digits (printf's %g) where
// they read back as `v`, else the fewest that do (read back as a float for a
// float option), so that two values never share a label.
template <class F>
std::string number_text(F v) {
  char text[40];
  for (int digits = 6; digits <= 17; ++digits) {
    std::snprintf(text, sizeof text, "%.*g", digits, static_cast<double>(v));
    const bool exact = std::is_same_v<F, float> ? std::strtof(text, nullptr) == static_cast<float>(v)
                                                : std::strtod(text, nullptr) == static_cast<double>(v);
    if (exact) break;
  }
  return text;
}

// The option's value as a variant spec writes it.
template <class T>
std::string value_text(const T& v) {
  if constexpr (kIsChoice<T>)
    return std::string(name_of(v));
  else if constexpr (std::is_same_v<T, bool>)
    return v ? "1" : "0";
  else if constexpr (std::is_integral_v<T>)
    return std::to_string(v);
  else
    return number_text(v);
}

double parse_number(const std::string& spec, const std::string& name, const std::string& value) {
  std::size_t used = 0;
  double v = 0;
  try {
    v = std::stod(value, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != value.size())
    throw Error(ErrorKind::Usage, "--variant '" + spec + "': " + name + " '" + value + "' is not a number");
  return v;
}

// Sets `field` from a variant spec's VALUE: a name of the choice's table,
// 0 or 1 for a flag, a number otherwise (its range is settings_from's).
template <class T>
void set_from_text(const std::string& spec, const std::string& name, const std::string& value, T& field) {
  if constexpr (kIsChoice<T>) {
    const std::optional<T> v = value_named<T>(value);
    if (!v)
      throw Error(ErrorKind::Usage,
                  "--variant '" + spec + "': " + name + " '" + value + "' is not one of " + names_joined<T>());
    field = *v;
  } else if constexpr (std::is_same_v<T, bool>) {
    if (value != "0" && value != "1")
      throw Error(ErrorKind::Usage, "--variant '" + spec + "': " + name + " '" + value + "' is not one of 0, 1");
    field = value == "1";
  } else if constexpr (std::is_integral_v<T>) {  // subpixel-bits: digits only, as the option takes it
    if (value.empty() || value.size() > 9 || value.find_first_not_of("0123456789") != std::string::npos)
      throw Error(ErrorKind::Usage, "--variant '" + spec + "': " + name + " '" + value + "' is not a whole number");
    field = static_cast<T>(std::stol(value));
  } else {
    field = static_cast<T>(parse_number(spec, name, value));
  }
}

}  // namespace

void add_emulation_options(CLI::App& cmd, EmulationOptions& options) {
  std::vector<std::string> names;
  visit_emulation_options(options, [&names](const EmulationOption& e, auto&) { names.emplace_back(e.name); });
  add_emulation_options(cmd, options, names);
}

void add_emulation_options(CLI::App& cmd, EmulationOptions& options, const std::vector<std::string>& names) {
  // The flags after the valued options.
  std::vector<std::pair<EmulationOption, bool*>> flags;
  std::size_t added = 0;
  visit_emulation_options(options, [&](const EmulationOption& e, auto& field) {
    using T = std::decay_t<decltype(field)>;
    if (std::find(names.begin(), names.end(), e.name) == names.end()) return;
    ++added;
    const std::string flag = std::string("--") + e.name;
    if constexpr (kIsChoice<T>) {
      add_choice_option(cmd, flag, field, std::string(e.lead) + ": " + values_described<T>() + e.tail);
    } else if constexpr (std::is_same_v<T, bool>) {
      flags.emplace_back(e, &field);
    } else if constexpr (std::is_integral_v<T>) {  // --subpixel-bits, the one whole number
      cmd.add_option(flag, field, e.lead)->transform(integer_in(0, 12))->capture_default_str();
    } else {
      cmd.add_option(flag, field, e.lead)->check(finite_number())->capture_default_str();
    }
  });
  for (auto& [e, field] : flags) cmd.add_flag(std::string("--") + e.name, *field, e.lead);
  NEARCAP_CHECK(added == names.size());  // every name is an emulation option's
}

std::vector<std::pair<std::string, std::string>> emulation_option_values(const EmulationOptions& options) {
  std::vector<std::pair<std::string, std::string>> values;
  visit_emulation_options(
      options, [&](const EmulationOption& e, const auto& field) { values.emplace_back(e.name, value_text(field)); });
  return values;
}

nlohmann::json emulation_choices_json() {
  nlohmann::json choices = nlohmann::json::array();
  EmulationOptions options;
  visit_emulation_options(options, [&](const EmulationOption& e, const auto& field) {
    using T = std::decay_t<decltype(field)>;
    if constexpr (kIsChoice<T>) {
      nlohmann::json values = nlohmann::json::array();
      for (const NamedValue<T>& v : table_of<T>())
        values.push_back({{"name", std::string(v.name)}, {"help", std::string(v.help)}});
      choices.push_back({{"option", e.name}, {"help", e.lead}, {"values", std::move(values)}});
    }
  });
  return choices;
}

EmulationOptions with_variant(const EmulationOptions& base, const std::string& spec) {
  EmulationOptions o = base;
  std::stringstream parts(spec);
  std::string part;
  bool any = false;
  std::set<std::string> given;
  while (std::getline(parts, part, ',')) {
    const std::size_t eq = part.find('=');
    if (eq == std::string::npos || eq == 0)
      throw Error(ErrorKind::Usage, "--variant '" + spec + "': expected NAME=VALUE, got '" + part + "'");
    const std::string name = part.substr(0, eq), value = part.substr(eq + 1);
    if (!given.insert(name).second)
      throw Error(ErrorKind::Usage, "--variant '" + spec + "': " + name + " is given twice");
    any = true;
    bool known = false;
    std::string valued, flags;  // the names, for the message: the flags last, as in the help
    visit_emulation_options(o, [&](const EmulationOption& e, auto& field) {
      std::string& list = std::is_same_v<std::decay_t<decltype(field)>, bool> ? flags : valued;
      list += (list.empty() ? "" : ", ") + std::string(e.name);
      if (name != e.name) return;
      known = true;
      set_from_text(spec, name, value, field);
    });
    if (!known)
      throw Error(ErrorKind::Usage,
                  "--variant '" + spec + "': unknown choice '" + name + "' (" + valued + ", " + flags + ")");
  }
  if (!any) throw Error(ErrorKind::Usage, "--variant '': expected NAME=VALUE");
  settings_from(o);  // the ranges
  return o;
}

std::string variant_label(const EmulationOptions& options) {
  const auto now = emulation_option_values(options), defaults = emulation_option_values(EmulationOptions{});
  std::string label;
  for (std::size_t k = 0; k < now.size(); ++k)
    if (now[k].second != defaults[k].second) label += (label.empty() ? "" : ",") + now[k].first + "=" + now[k].second;
  return label.empty() ? "default" : label;
}

gl::EmulationSettings settings_from(const EmulationOptions& o) {
  gl::EmulationSettings s = o.settings;
  if (s.raster.subpixel_bits < 0 || s.raster.subpixel_bits > 12)
    throw Error(ErrorKind::Usage, "--subpixel-bits " + std::to_string(s.raster.subpixel_bits) + " is not in [0, 12]");
  if (!(s.raster.guard_band >= 1.0f) || !std::isfinite(s.raster.guard_band))
    throw Error(ErrorKind::Usage,
                "--guard-band must be at least 1 (1 clips x and y at the view volume) and a finite float32");
  s.raster.mesa_clipper = o.clipper == gl::ClipperArithmetic::Mesa;
  s.arithmetic = o.fma ? gl::Arithmetic::Fused : gl::Arithmetic::Separate;
  if (!(s.light_frustum.near_scale > 0 && s.light_frustum.near_scale <= 1))
    throw Error(ErrorKind::Usage,
                "--l-near-scale must be in (0, 1] (a margin below the rule's l_near; above it clips the occluder)");
  if (s.depth_mapping == gl::DepthMapping::Reversed && s.infinite_far != gl::InfiniteFar::Exact)
    throw Error(ErrorKind::Usage, "--infinite-far " + std::string(name_of(s.infinite_far)) +
                                      " nudges the standard depth row; --depth-mapping reversed puts infinity at "
                                      "depth 0 exactly (use --infinite-far exact)");
  return s;
}

namespace {

// <prefix>/share/nearcap when this program runs from <prefix>/bin with its
// data installed; empty otherwise.
std::filesystem::path installed_share_dir() {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) return {};
  const std::filesystem::path share = (exe.parent_path() / NEARCAP_INSTALLED_SHARE_FROM_BIN).lexically_normal();
  if (!std::filesystem::is_regular_file(share / "policy.json", ec)) return {};
  return share;
}

}  // namespace

std::string shipped_data_dir() {
  const std::filesystem::path share = installed_share_dir();
  return share.empty() ? std::string(NEARCAP_DATA_DIR) : share.string();
}

std::string shipped_scripts_dir() {
  const std::filesystem::path share = installed_share_dir();
  return share.empty() ? std::string(NEARCAP_ANALYSIS_DIR) : share.string();
}

std::string bundled_path_file(const std::string& name) {
  std::error_code ec;
  if (name.empty() || name.find('/') != std::string::npos || std::filesystem::exists(name, ec)) return "";
  const bool named_json = name.size() > 5 && name.compare(name.size() - 5, 5, ".json") == 0;
  const std::string bundled = shipped_data_dir() + "/paths/" + name + (named_json ? "" : ".json");
  return std::filesystem::exists(bundled, ec) ? bundled : "";
}

analysis::CameraPath load_camera_path_file(const std::string& file, MeshCache* meshes) {
  const std::string bundled = bundled_path_file(file);
  if (!bundled.empty())
    throw Error(ErrorKind::Io, file +
                                   ": cannot open the camera path file (no such file; the bundled path of that "
                                   "name is " +
                                   bundled + ")");
  return analysis::load_camera_path(file, meshes);
}

analysis::SamplerSpec sampler_spec(const SamplerOptions& o) {
  analysis::SamplerSpec spec;
  spec.seed = o.seed;
  if (o.kinds != "all") {
    spec.kinds.clear();
    // Each kind once: a kind named twice would be drawn twice as often.
    for (const std::string& name : comma_separated(o.kinds)) {
      if (name.empty()) throw Error(ErrorKind::Usage, "--kinds '" + o.kinds + "': an empty kind name");
      refuse_list_word("--kinds", name);
      const std::optional<analysis::HardCaseKind> kind = value_named<analysis::HardCaseKind>(name);
      if (!kind)
        throw Error(ErrorKind::Usage, "--kinds: '" + name + "' is not a hard-case kind (one of " +
                                          names_joined<analysis::HardCaseKind>() + ", or all)");
      if (std::find(spec.kinds.begin(), spec.kinds.end(), *kind) != spec.kinds.end())
        throw Error(ErrorKind::Usage, "--kinds '" + o.kinds + "': " + name + " is named twice");
      spec.kinds.push_back(*kind);
    }
  }
  spec.width = o.width;
  spec.height = o.height;
  spec.allow_bunny = o.allow_bunny;
  // The bundled meshes: the environment's NEARCAP_DATA_DIR, or the shipped data.
  const char* data = std::getenv("NEARCAP_DATA_DIR");
  spec.mesh_directory = (std::filesystem::path(data && *data ? data : shipped_data_dir()) / "meshes").string();
  return spec;
}

void check_camera_path_names(const std::vector<std::string>& paths) {
  for (std::size_t k = 0; k < paths.size(); ++k) {
    if (io::first_non_utf8(paths[k]) != std::string::npos || io::first_control_character(paths[k]) != std::string::npos)
      throw Error(ErrorKind::Usage, "--path " + paths[k] +
                                        ": a file name that is not UTF-8 text, or holds a control character, cannot "
                                        "name rows (it goes into CSV fields); rename the file");
    for (std::size_t j = 0; j < k; ++j) {
      std::error_code ec;  // a missing file is reported where it is read
      if (paths[j] == paths[k] || std::filesystem::equivalent(paths[j], paths[k], ec))
        throw Error(ErrorKind::Usage, "--path " + paths[k] + " is given twice");
      const std::string name = std::filesystem::path(paths[k]).stem().string();
      if (std::filesystem::path(paths[j]).stem().string() == name)
        throw Error(ErrorKind::Usage, "--path " + paths[j] + " and --path " + paths[k] + " are both named '" + name +
                                          "': their rows' configuration ids (path:" + name +
                                          ":FRAME) would be the same; give one a file name of its own");
    }
  }
}

void RejectedConfigurations::add(const std::string& id, const Error& e) {
  if (count_++ == 0) {
    first_id_ = id;
    // The reading's error names the scene by its id already.
    const std::string what = e.what(), named = id + ": ";
    first_reason_ = what.rfind(named, 0) == 0 ? what.substr(named.size()) : what;
    first_kind_ = e.kind();
  }
}

std::string RejectedConfigurations::sentence() const {
  return std::to_string(count_) +
         (count_ > 1 ? " configurations rejected (they do not load; the first, " : " configuration rejected (") +
         first_id_ + ": " + first_reason_ + ")";
}

void RejectedConfigurations::refuse_all_rejected(std::size_t total) const {
  if (total > 0 && count_ == total)
    throw Error(first_kind_, "nothing measured: " +
                                 (total > 1 ? "none of the " + std::to_string(total) +
                                                  " configurations loads (the first, " + first_id_
                                            : "the configuration " + first_id_ + " does not load (") +
                                 ": " + first_reason_ + ")");
}

void check_sampler_meshes(const analysis::SamplerSpec& spec) {
  const char* data = std::getenv("NEARCAP_DATA_DIR");
  if (!data || !*data) return;  // the shipped meshes, which the tests read
  // Each mesh the sampler may name, read and validated as an occluder: a
  // folder that lacks one, or holds a broken one, would otherwise reject
  // every configuration that names it, one by one.
  MeshCache meshes;
  for (const std::string& file : analysis::sampler_mesh_files(spec)) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec))
      throw Error(ErrorKind::Io, "NEARCAP_DATA_DIR=" + std::string(data) + ": no " + file +
                                     " (the sampler reads its meshes from $NEARCAP_DATA_DIR/meshes)");
    try {
      meshes.get(file, true);
    } catch (const Error& e) {
      throw Error(e.kind(),
                  "NEARCAP_DATA_DIR=" + std::string(data) + ": a mesh of the sampler does not load: " + e.what());
    }
  }
}

CLI::Option* add_samples_option(CLI::App& cmd, std::uint64_t& samples, const std::string& help, std::uint64_t lo,
                                std::uint64_t hi) {
  return cmd.add_option("--samples", samples, help)->transform(integer_in(lo, hi));
}

void add_viewport_options(CLI::App& cmd, int& width, int& height, const std::string& width_default,
                          const std::string& height_default) {
  CLI::Option* w = cmd.add_option("--width", width, "viewport width of every configuration" + width_default)
                       ->transform(integer_in(1, kMaxViewportPixels));
  CLI::Option* h = cmd.add_option("--height", height, "viewport height of every configuration" + height_default)
                       ->transform(integer_in(1, kMaxViewportPixels));
  if (width_default.empty()) w->capture_default_str();
  if (height_default.empty()) h->capture_default_str();
}

void refuse_unread_sampler_options(const SamplerOptions& o, std::uint64_t samples) {
  if (samples == 0 && !o.given.empty())
    throw Error(ErrorKind::Usage, o.given + " is read only with --samples: this command samples nothing");
}

void add_sampler_options(CLI::App& cmd, SamplerOptions& o, bool sizes) {
  const auto note = [&o](const char* name) {
    return [&o, name](const std::string&) {
      if (o.given.empty()) o.given = name;
    };
  };
  cmd.add_option("--seed", o.seed, "the sampler's seed")
      ->transform(integer_in(0, std::numeric_limits<std::uint64_t>::max()))
      ->each(note("--seed"))
      ->capture_default_str();
  std::string by_name_only;
  for (analysis::HardCaseKind k : values_of<analysis::HardCaseKind>())
    if (analysis::asked_for_by_name_only(k))
      by_name_only += (by_name_only.empty() ? "" : " and ") + std::string(name_of(k));
  cmd.add_option("--kinds", o.kinds,
                 "comma-separated hard-case kinds (" + names_joined<analysis::HardCaseKind>() +
                     ") or all (every kind but " + by_name_only + ")")
      ->each(note("--kinds"))
      ->capture_default_str();
  if (sizes) add_viewport_options(cmd, o.width, o.height);
  cmd.add_flag("--allow-bunny", o.allow_bunny, "the 75k-triangle bunny among the real meshes")
      ->each(note("--allow-bunny"));
}

std::vector<std::string> comma_separated(const std::string& names) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (start <= names.size()) {
    const std::size_t comma = std::min(names.find(',', start), names.size());
    out.push_back(names.substr(start, comma - start));
    start = comma + 1;
  }
  return out;
}

void refuse_list_word(const std::string& option, const std::string& name, std::initializer_list<const char*> words) {
  for (const char* word : words)
    if (name == word) throw Error(ErrorKind::Usage, option + " " + name + " stands alone: give it without other names");
}

MethodChoice method_choice(const std::string& names, bool lists_raytrace) {
  MethodChoice c;
  if (names == "all") {
    c.methods = methods_from("all", "--method");
    c.raytrace = true;
    c.policy = true;
    return c;
  }
  std::string rest;
  std::set<std::string> seen;
  for (const std::string& name : comma_separated(names)) {
    refuse_list_word("--method", name);
    if (name != "policy" && name != "raytrace" && !gl::shadow_method_from_string(name))
      throw Error(ErrorKind::Usage, "--method '" + name + "' is not one of " + names_joined<gl::ShadowMethod>() +
                                        (lists_raytrace ? ", raytrace" : "") + ", policy (or all)");
    if (!seen.insert(name).second) throw Error(ErrorKind::Usage, "--method names " + name + " twice");
    if (name == "policy")
      c.policy = true;
    else if (name == "raytrace")
      c.raytrace = true;
    else
      rest += (rest.empty() ? "" : ",") + name;
  }
  if (!rest.empty() || (!c.policy && !c.raytrace)) c.methods = methods_from(rest, "--method");
  return c;
}

nlohmann::json policy_occluders_json(const Scene& scene, const analysis::PolicyDecision& d) {
  nlohmann::json occluders = nlohmann::json::array();
  for (std::size_t o = 0; o < scene.objects.size(); ++o)
    if (scene.objects[o].occluder)
      occluders.push_back(
          {{"object", o}, {"method", std::string(to_string(d.object_methods[o]))}, {"why", d.reason(o)}});
  return occluders;
}

std::vector<gl::ShadowMethod> methods_from(const std::string& names, const std::string& option) {
  if (names == "all") return {gl::kAllShadowMethods.begin(), gl::kAllShadowMethods.end()};
  std::vector<gl::ShadowMethod> methods;
  for (const std::string& name : comma_separated(names)) {
    refuse_list_word(option, name);
    const auto m = gl::shadow_method_from_string(name);
    if (!m)
      throw Error(ErrorKind::Usage,
                  option + " '" + name + "' is not one of " + names_joined<gl::ShadowMethod>() + " (or all)");
    methods.push_back(*m);
  }
  return methods;
}

void print_case_legend(std::ostream& out) {
  out << "cases: where the camera's near plane cuts a silhouette edge's infinite side quad (ZP+ section 5)\n"
         "  A   not at all: nothing to correct\n"
         "  B   both infinite edges: the clipped vertices move to their near-cap counterparts (exact)\n"
         "  C1  an infinite edge and the silhouette edge: counterparts plus a corrective quad\n"
         "  C2  an infinite edge and the edge at infinity: counterparts plus a corrective quad\n"
         "  D   the silhouette edge and the edge at infinity (light near the near plane): ZP+ switches to Z-fail\n"
         "  degen(erate)  the plane holds a quad vertex or is parallel to an infinite edge\n";
}

void check_light_index(const Scene& scene, std::size_t light) {
  if (light >= scene.lights.size())
    throw Error(ErrorKind::Usage, scene.source + ": --light " + std::to_string(light) +
                                      " is out of range (the scene has " + std::to_string(scene.lights.size()) +
                                      " light(s))");
}

namespace {

// The child being waited for, and the signal this process received meanwhile.
volatile sig_atomic_t g_interrupting_signal = 0;
volatile sig_atomic_t g_child = 0;  // a pid_t (an int here)

// SIGINT, SIGTERM or SIGHUP while a child runs: the child gets SIGTERM, which
// the report script turns into an exit that runs its cleanup (its staging
// folder is removed), and this process waits for it to end.
void interrupt_child(int signal) {
  const int saved = errno;
  g_interrupting_signal = signal;
  if (g_child > 0) ::kill(static_cast<pid_t>(g_child), SIGTERM);
  errno = saved;
}

// The signals a child is stopped by, and this process's mask and handlers of
// them while it runs one.  A signal the process ignores (`nohup`, a shell's
// background job) stays ignored, here and in the child.  The signals are
// blocked from construction to start(), so that none arrives between the
// child's spawn and the handlers that forward it.
class ChildInterrupts {
 public:
  ChildInterrupts() {
    g_interrupting_signal = 0;
    g_child = 0;
    const sigset_t stops = stop_signals();
    ::pthread_sigmask(SIG_BLOCK, &stops, &mask_);
  }
  // The mask the child starts with: this process's before construction.
  const sigset_t& child_mask() const { return mask_; }
  // Forwards the signals to `child` from now on.
  void start(pid_t child) {
    g_child = child;
    struct sigaction forward {};
    forward.sa_handler = interrupt_child;
    sigemptyset(&forward.sa_mask);
    for (std::size_t k = 0; k < kSignals.size(); ++k) {
      ::sigaction(kSignals[k], nullptr, &previous_[k]);
      if (previous_[k].sa_handler != SIG_IGN) ::sigaction(kSignals[k], &forward, nullptr);
    }
    started_ = true;
    ::pthread_sigmask(SIG_SETMASK, &mask_, nullptr);
  }
  // The handlers and the mask as they were before construction; nothing is
  // forwarded any more.
  void stop() {
    if (stopped_) return;
    stopped_ = true;
    const sigset_t stops = stop_signals();
    ::pthread_sigmask(SIG_BLOCK, &stops, nullptr);
    g_child = 0;
    if (started_)
      for (std::size_t k = 0; k < kSignals.size(); ++k) ::sigaction(kSignals[k], &previous_[k], nullptr);
    ::pthread_sigmask(SIG_SETMASK, &mask_, nullptr);
  }
  ~ChildInterrupts() { stop(); }
  ChildInterrupts(const ChildInterrupts&) = delete;
  ChildInterrupts& operator=(const ChildInterrupts&) = delete;

 private:
  static constexpr std::array<int, 3> kSignals{SIGINT, SIGTERM, SIGHUP};
  static sigset_t stop_signals() {
    sigset_t stops;
    sigemptyset(&stops);
    for (int s : kSignals) sigaddset(&stops, s);
    return stops;
  }
  sigset_t mask_{};
  std::array<struct sigaction, 3> previous_{};
  bool started_ = false, stopped_ = false;
};

// Spawns Python on the script; its stderr goes to `stderr_fd` when not -1.
// Returns waitpid's raw status; throws Interrupted when this process was
// signalled while Python ran (once Python has ended).
int spawn_python(const std::string& script, const std::vector<std::string>& args, const std::string& what,
                 int stderr_fd) {
  const char* env = std::getenv("NEARCAP_PYTHON");
  const std::string py = env && *env ? env : (::access("/usr/bin/python3", X_OK) == 0 ? "/usr/bin/python3" : "python3");
  std::vector<std::string> all{py, script};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  ::posix_spawn_file_actions_init(&actions);
  if (stderr_fd >= 0) ::posix_spawn_file_actions_adddup2(&actions, stderr_fd, STDERR_FILENO);
  int status = 0;
  ChildInterrupts interrupts;
  posix_spawnattr_t attributes;
  ::posix_spawnattr_init(&attributes);
  ::posix_spawnattr_setsigmask(&attributes, &interrupts.child_mask());
  ::posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGMASK);
  pid_t pid = 0;
  const int spawned = ::posix_spawnp(&pid, py.c_str(), &actions, &attributes, argv.data(), environ);
  ::posix_spawnattr_destroy(&attributes);
  ::posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0)
    throw Error(ErrorKind::Io, py + ": cannot run Python for " + what + ": " + std::strerror(spawned) +
                                   " (scripts/install-deps.sh installs python3 and python3-matplotlib)");
  interrupts.start(pid);
  // Waited for without reaping it, so that a signal forwarded before the
  // handlers are restored reaches this child (a zombie) and no process that
  // took its number; then reaped.
  siginfo_t info{};
  while (::waitid(P_PID, static_cast<id_t>(pid), &info, WEXITED | WNOWAIT) < 0)
    if (errno != EINTR) throw Error(ErrorKind::Io, "waiting for " + what + ": " + std::string(std::strerror(errno)));
  interrupts.stop();
  while (::waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) throw Error(ErrorKind::Io, "waiting for " + what + ": " + std::string(std::strerror(errno)));
  if (g_interrupting_signal != 0) throw Interrupted{g_interrupting_signal};
  return status;
}

}  // namespace

int run_python_script_logged(const std::string& script, const std::vector<std::string>& args, const std::string& what,
                             int stderr_fd) {
  return spawn_python(script, args, what, stderr_fd);
}

}  // namespace nearcap::cli
