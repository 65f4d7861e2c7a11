#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <initializer_list>
#include <limits>
#include <sstream>
#include <utility>

#include "cli_commands.hpp"
#include "nearcap/error.hpp"

extern char** environ;

namespace nearcap::cli {
namespace {

std::string joined(const std::vector<std::string>& names) {
  std::string list;
  for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
  return list;
}

}  // namespace

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
        errno = 0;
        const double d = std::strtod(value.c_str(), &end);
        const bool ok = !value.empty() && end == value.c_str() + value.size() && errno != ERANGE && std::isfinite(d);
        return ok ? std::string() : "'" + value + "' is not a finite number";
      },
      "FINITE");
}

CLI::Option* add_light_option(CLI::App& cmd, std::size_t& light, bool required) {
  const CLI::Validator digits(
      [](std::string& value) -> std::string {
        const bool ok = !value.empty() && value.size() <= 9 &&
                        std::all_of(value.begin(), value.end(), [](char c) { return c >= '0' && c <= '9'; });
        return ok ? std::string() : "'" + value + "' is not a light index (a non-negative integer)";
      },
      "INDEX");
  CLI::Option* option = cmd.add_option("--light", light, "index of the light in the scene's list (0, 1, ...)");
  option->required(required)->check(digits);
  return option;
}

void add_max_memory_option(CLI::App& cmd, double& max_memory_gb) {
  cmd.add_option("--max-memory", max_memory_gb,
                 "refuse a frame whose estimated memory exceeds this many GB (default: 3/4 of the machine's memory)")
      ->check(finite_number())
      ->check(CLI::PositiveNumber);
}

void check_memory_estimate(const Scene& scene, const std::string& command, double bytes_per_pixel,
                           double max_memory_gb) {
  const double pixels = static_cast<double>(scene.camera.width) * scene.camera.height;
  const double estimate = 64e6 + bytes_per_pixel * pixels;
  double limit = max_memory_gb * 1e9;
  if (limit <= 0) {
    const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
    limit = pages > 0 && page > 0 ? 0.75 * static_cast<double>(pages) * static_cast<double>(page) : 8e9;
  }
  if (estimate <= limit) return;
  char message[320];
  std::snprintf(message, sizeof message,
                "%s: %s at %dx%d needs about %.1f GB (%.0f bytes per pixel), over the limit of %.1f GB; lower "
                "width/height in the scene, or raise the limit with --max-memory GB",
                scene.source.c_str(), command.c_str(), scene.camera.width, scene.camera.height, estimate / 1e9,
                bytes_per_pixel, limit / 1e9);
  throw Error(ErrorKind::Resource, message);
}

void add_emulation_options(CLI::App& cmd, EmulationOptions& o) {
  cmd.add_option("--subpixel-bits", o.subpixel_bits, "fixed-point sub-pixel bits of the rasterizer")
      ->transform(integer_in(0, 12))
      ->capture_default_str();
  cmd.add_option("--depth", o.depth, "depth buffer: fixed24 or float32")
      ->check(CLI::IsMember({"fixed24", "float32"}))
      ->capture_default_str();
  cmd.add_option("--fill-rule", o.fill_rule,
                 "pixel centres on an edge: bottom-left (llvmpipe's, GL window coordinates) or top-left")
      ->check(CLI::IsMember({"top-left", "bottom-left"}))
      ->capture_default_str();
  cmd.add_option("--guard-band", o.guard_band,
                 "x/y clipping at |x|,|y| <= G w: 1 is llvmpipe's view-volume clip, larger a GPU-style guard band")
      ->check(finite_number())
      ->capture_default_str();
  cmd.add_option("--viewport", o.viewport,
                 "perspective divide and viewport arithmetic: divide ((x/w + 1) W/2) or llvmpipe (1/w, then "
                 "fused multiply-add where Mesa fuses: what llvmpipe computes)")
      ->check(CLI::IsMember({"divide", "llvmpipe"}))
      ->capture_default_str();
  cmd.add_option("--depth-interpolation", o.depth_interpolation,
                 "a fragment's depth: exact (from exact barycentrics, rounded once) or llvmpipe (Mesa's float32 "
                 "plane and 24-bit conversion)")
      ->check(CLI::IsMember({"exact", "llvmpipe"}))
      ->capture_default_str();
  cmd.add_option("--clipper", o.clipper,
                 "the clipper's arithmetic: inside (intersections from the inside vertex) or mesa (Mesa's plane "
                 "order, from the outside vertex, its fan order); --viewport llvmpipe --depth-interpolation llvmpipe "
                 "--clipper mesa is the llvmpipe model")
      ->check(CLI::IsMember({"inside", "mesa"}))
      ->capture_default_str();
  cmd.add_option("--light-projection", o.light_projection,
                 "P_l formulation: paper, glfrustum, composed (P_l M_l MV in double, rounded once), rebased "
                 "(origin at the near rectangle's centre) or clipped-sides (no light frustum: the near-cap is the "
                 "fan over the edges the clipper leaves in the near plane)")
      ->check(CLI::IsMember(light_projection_names()))
      ->capture_default_str();
  cmd.add_option("--l-near", o.l_near,
                 "how ZP+'s light frustum picks l_near: paper-ratio (l_far min(d / d_max, 1/2)), exact-max (the "
                 "largest admissible, exactly, capped at l_far / 2) or near-clamp (depth clamp at the near side)")
      ->check(CLI::IsMember({"paper-ratio", "exact-max", "near-clamp"}))
      ->capture_default_str();
  cmd.add_option("--l-near-scale", o.l_near_scale, "l_near multiplied by this safety margin in (0, 1]")
      ->check(finite_number())
      ->capture_default_str();
  cmd.add_option("--zfail-far", o.zfail_far,
                 "zfail's far plane: infinite, clamp (GL_DEPTH_CLAMP), clamp-far (far plane only) or far-cap (ZF+: "
                 "no clamp, the far-plane cap of the clipped volume)")
      ->check(CLI::IsMember({"infinite", "clamp", "clamp-far", "far-cap"}))
      ->capture_default_str();
  cmd.add_option("--switch-clamp", o.switch_clamp,
                 "depth clamp of ZP+'s switch to zfail (case D, no light frustum): clamp, clamp-far or far-cap "
                 "(ZF+: no clamp, the far-plane cap)")
      ->check(CLI::IsMember({"clamp", "clamp-far", "far-cap"}))
      ->capture_default_str();
  cmd.add_option("--zpass-far", o.zpass_far,
                 "zpass's projection: finite (its own frustum) or infinite (the infinite far plane, as Doom 3 "
                 "draws; kept finite in a frame with a ZP+ method)")
      ->check(CLI::IsMember({"finite", "infinite"}))
      ->capture_default_str();
  cmd.add_option("--infinite-far", o.infinite_far,
                 "the infinite projection's depth row: exact (-1, -2 near), epsilon (Everitt and Kilgard's 2^-22 "
                 "margin), doom3 (-0.999) or one-ulp (-(1 - 2^-23))")
      ->check(CLI::IsMember(infinite_far_names()))
      ->capture_default_str();
  cmd.add_option("--depth-mapping", o.depth_mapping,
                 "the camera's depth: standard (GL's -1..1 clip depth, near at 0, GL_LESS) or reversed "
                 "(glClipControl GL_ZERO_TO_ONE, near at 1, far or infinity at 0, GL_GREATER: with --depth float32, "
                 "reversed-Z)")
      ->check(CLI::IsMember(depth_mapping_names()))
      ->capture_default_str();
  cmd.add_option("--near-plane", o.near_plane,
                 "the camera's near plane: scene (the scene file's) or tight (moved out to half the depth of the "
                 "nearest point in view, when farther: the same image, more depth precision)")
      ->check(CLI::IsMember(near_plane_names()))
      ->capture_default_str();
  cmd.add_option("--volume-culling", o.volume_culling,
                 "each occluder's draws limited to where its volume can change a pixel: none, scissor (glScissor), "
                 "depth-bounds (GL_EXT_depth_bounds_test) or both; the same stencil, fewer fragments")
      ->check(CLI::IsMember(gl::volume_culling_names()))
      ->capture_default_str();
  cmd.add_flag("--fma", o.fma,
               "vertex transforms with fused multiply-add (a GPU that fuses; llvmpipe's GLSL fma() does not)");
}

namespace {

// The emulation options by name, as text: what a variant spec overrides.
std::vector<std::pair<std::string, std::string>> option_values(const EmulationOptions& o) {
  auto number = [](double v) {
    std::ostringstream s;
    s << v;
    return s.str();
  };
  return {{"subpixel-bits", std::to_string(o.subpixel_bits)},
          {"depth", o.depth},
          {"fill-rule", o.fill_rule},
          {"guard-band", number(o.guard_band)},
          {"viewport", o.viewport},
          {"depth-interpolation", o.depth_interpolation},
          {"clipper", o.clipper},
          {"light-projection", o.light_projection},
          {"l-near", o.l_near},
          {"l-near-scale", number(o.l_near_scale)},
          {"zfail-far", o.zfail_far},
          {"switch-clamp", o.switch_clamp},
          {"zpass-far", o.zpass_far},
          {"infinite-far", o.infinite_far},
          {"fma", o.fma ? "1" : "0"},
          {"depth-mapping", o.depth_mapping},
          {"near-plane", o.near_plane},
          {"volume-culling", o.volume_culling}};
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

void need_one_of(const std::string& spec, const std::string& name, const std::string& value,
                 const std::vector<std::string>& allowed) {
  for (const std::string& a : allowed)
    if (value == a) return;
  const std::string list = joined(allowed);
  throw Error(ErrorKind::Usage, "--variant '" + spec + "': " + name + " '" + value + "' is not one of " + list);
}

}  // namespace

std::vector<std::pair<std::string, std::string>> emulation_option_values(const EmulationOptions& options) {
  return option_values(options);
}

EmulationOptions with_variant(const EmulationOptions& base, const std::string& spec) {
  EmulationOptions o = base;
  std::stringstream parts(spec);
  std::string part;
  bool any = false;
  while (std::getline(parts, part, ',')) {
    const std::size_t eq = part.find('=');
    if (eq == std::string::npos || eq == 0)
      throw Error(ErrorKind::Usage, "--variant '" + spec + "': expected NAME=VALUE, got '" + part + "'");
    const std::string name = part.substr(0, eq), value = part.substr(eq + 1);
    any = true;
    if (name == "subpixel-bits") {
      o.subpixel_bits = static_cast<int>(parse_number(spec, name, value));
    } else if (name == "depth") {
      need_one_of(spec, name, value, {"fixed24", "float32"});
      o.depth = value;
    } else if (name == "fill-rule") {
      need_one_of(spec, name, value, {"bottom-left", "top-left"});
      o.fill_rule = value;
    } else if (name == "guard-band") {
      o.guard_band = static_cast<float>(parse_number(spec, name, value));
    } else if (name == "viewport") {
      need_one_of(spec, name, value, {"divide", "llvmpipe"});
      o.viewport = value;
    } else if (name == "depth-interpolation") {
      need_one_of(spec, name, value, {"exact", "llvmpipe"});
      o.depth_interpolation = value;
    } else if (name == "clipper") {
      need_one_of(spec, name, value, {"inside", "mesa"});
      o.clipper = value;
    } else if (name == "light-projection") {
      need_one_of(spec, name, value, light_projection_names());
      o.light_projection = value;
    } else if (name == "l-near") {
      need_one_of(spec, name, value, {"paper-ratio", "exact-max", "near-clamp"});
      o.l_near = value;
    } else if (name == "l-near-scale") {
      o.l_near_scale = parse_number(spec, name, value);
    } else if (name == "zfail-far") {
      need_one_of(spec, name, value, {"infinite", "clamp", "clamp-far", "far-cap"});
      o.zfail_far = value;
    } else if (name == "switch-clamp") {
      need_one_of(spec, name, value, {"clamp", "clamp-far", "far-cap"});
      o.switch_clamp = value;
    } else if (name == "zpass-far") {
      need_one_of(spec, name, value, {"finite", "infinite"});
      o.zpass_far = value;
    } else if (name == "infinite-far") {
      need_one_of(spec, name, value, infinite_far_names());
      o.infinite_far = value;
    } else if (name == "fma") {
      need_one_of(spec, name, value, {"0", "1"});
      o.fma = value == "1";
    } else if (name == "depth-mapping") {
      need_one_of(spec, name, value, depth_mapping_names());
      o.depth_mapping = value;
    } else if (name == "near-plane") {
      need_one_of(spec, name, value, near_plane_names());
      o.near_plane = value;
    } else if (name == "volume-culling") {
      need_one_of(spec, name, value, gl::volume_culling_names());
      o.volume_culling = value;
    } else {
      throw Error(ErrorKind::Usage,
                  "--variant '" + spec + "': unknown choice '" + name +
                      "' (subpixel-bits, depth, fill-rule, guard-band, viewport, depth-interpolation, clipper, "
                      "light-projection, "
                      "l-near, l-near-scale, zfail-far, switch-clamp, zpass-far, infinite-far, "
                      "depth-mapping, near-plane, volume-culling, fma)");
    }
  }
  if (!any) throw Error(ErrorKind::Usage, "--variant '': expected NAME=VALUE");
  settings_from(o);  // the ranges
  return o;
}

std::string variant_label(const EmulationOptions& options) {
  const auto now = option_values(options), defaults = option_values(EmulationOptions{});
  std::string label;
  for (std::size_t k = 0; k < now.size(); ++k)
    if (now[k].second != defaults[k].second) label += (label.empty() ? "" : ",") + now[k].first + "=" + now[k].second;
  return label.empty() ? "default" : label;
}

gl::EmulationSettings settings_from(const EmulationOptions& o) {
  gl::EmulationSettings s;
  if (o.subpixel_bits < 0 || o.subpixel_bits > 12)
    throw Error(ErrorKind::Usage, "--subpixel-bits " + std::to_string(o.subpixel_bits) + " is not in [0, 12]");
  s.raster.subpixel_bits = o.subpixel_bits;
  s.raster.fill_rule = o.fill_rule == "top-left" ? gl::FillRule::TopLeft : gl::FillRule::BottomLeft;
  if (!(o.guard_band >= 1.0f))
    throw Error(ErrorKind::Usage, "--guard-band must be at least 1 (1 clips x and y at the view volume)");
  s.raster.guard_band = o.guard_band;
  s.raster.viewport = o.viewport == "llvmpipe" ? gl::ViewportArithmetic::Llvmpipe : gl::ViewportArithmetic::Divide;
  s.raster.depth =
      o.depth_interpolation == "llvmpipe" ? gl::DepthInterpolation::Llvmpipe : gl::DepthInterpolation::Exact;
  s.raster.mesa_clipper = o.clipper == "mesa";
  s.depth = o.depth == "fixed24" ? gl::DepthFormat::Fixed24 : gl::DepthFormat::Float32;
  s.arithmetic = o.fma ? gl::Arithmetic::Fused : gl::Arithmetic::Separate;
  const auto projection = gl::light_projection_from_string(o.light_projection);
  if (!projection)
    throw Error(ErrorKind::Usage,
                "--light-projection '" + o.light_projection + "' is not one of " + joined(light_projection_names()));
  s.light_frustum.projection = *projection;
  if (!(o.l_near_scale > 0 && o.l_near_scale <= 1))
    throw Error(ErrorKind::Usage,
                "--l-near-scale must be in (0, 1] (a margin below the rule's l_near; above it clips the occluder)");
  s.light_frustum.near_scale = o.l_near_scale;
  const auto rule = gl::light_near_rule_from_string(o.l_near);
  if (!rule)
    throw Error(ErrorKind::Usage, "--l-near '" + o.l_near + "' is not one of paper-ratio, exact-max, near-clamp");
  s.light_frustum.near_rule = *rule;
  s.zfail_far = *gl::zfail_far_from_string(o.zfail_far);
  s.switch_clamp = *gl::switch_clamp_from_string(o.switch_clamp);
  s.zpass_far = *gl::zpass_far_from_string(o.zpass_far);
  const auto infinite_far = gl::infinite_far_from_string(o.infinite_far);
  if (!infinite_far)
    throw Error(ErrorKind::Usage,
                "--infinite-far '" + o.infinite_far + "' is not one of " + joined(infinite_far_names()));
  s.infinite_far = *infinite_far;
  const auto mapping = gl::depth_mapping_from_string(o.depth_mapping);
  if (!mapping) throw Error(ErrorKind::Usage, "--depth-mapping '" + o.depth_mapping + "' is not standard or reversed");
  s.depth_mapping = *mapping;
  const auto near_plane = gl::near_plane_from_string(o.near_plane);
  if (!near_plane) throw Error(ErrorKind::Usage, "--near-plane '" + o.near_plane + "' is not scene or tight");
  s.near_plane = *near_plane;
  const auto culling = gl::volume_culling_from_string(o.volume_culling);
  if (!culling)
    throw Error(ErrorKind::Usage,
                "--volume-culling '" + o.volume_culling + "' is not one of " + joined(gl::volume_culling_names()));
  s.volume_culling = *culling;
  if (s.depth_mapping == gl::DepthMapping::Reversed && s.infinite_far != gl::InfiniteFar::Exact)
    throw Error(ErrorKind::Usage, "--infinite-far " + o.infinite_far +
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

analysis::SamplerSpec sampler_spec(const SamplerOptions& o) {
  analysis::SamplerSpec spec;
  spec.seed = o.seed;
  if (o.kinds != "all") {
    spec.kinds.clear();
    std::stringstream names(o.kinds);
    std::string name;
    while (std::getline(names, name, ',')) spec.kinds.push_back(analysis::hard_case_kind_from_string(name));
  }
  spec.width = o.width;
  spec.height = o.height;
  spec.allow_bunny = o.allow_bunny;
  // The bundled meshes: the environment's NEARCAP_DATA_DIR, or the shipped data.
  const char* data = std::getenv("NEARCAP_DATA_DIR");
  spec.mesh_directory = (std::filesystem::path(data && *data ? data : shipped_data_dir()) / "meshes").string();
  return spec;
}

void add_sampler_options(CLI::App& cmd, SamplerOptions& o, bool sizes) {
  cmd.add_option("--seed", o.seed, "the sampler's seed")
      ->transform(integer_in(0, std::numeric_limits<std::uint64_t>::max()))
      ->capture_default_str();
  cmd.add_option("--kinds", o.kinds,
                 "comma-separated hard-case kinds (light-near-plane, light-in-near-plane, grazing, eye-in-shadow, "
                 "far-from-origin, tiny-near, straddling, several-occluders, several-lights, real-mesh, "
                 "eye-near-volume) or all (every kind but eye-near-volume)")
      ->capture_default_str();
  if (sizes) {
    cmd.add_option("--width", o.width, "viewport width of every configuration")
        ->transform(integer_in(1, kMaxViewportPixels))
        ->capture_default_str();
    cmd.add_option("--height", o.height, "viewport height of every configuration")
        ->transform(integer_in(1, kMaxViewportPixels))
        ->capture_default_str();
  }
  cmd.add_flag("--allow-bunny", o.allow_bunny, "the 75k-triangle bunny among the real meshes");
}

const std::vector<std::string>& light_projection_names() {
  static const std::vector<std::string> names{"paper", "glfrustum", "composed", "rebased", "clipped-sides"};
  return names;
}

const std::vector<std::string>& depth_mapping_names() {
  static const std::vector<std::string> names{std::string(gl::to_string(gl::DepthMapping::Standard)),
                                              std::string(gl::to_string(gl::DepthMapping::Reversed))};
  return names;
}

const std::vector<std::string>& near_plane_names() {
  static const std::vector<std::string> names{std::string(gl::to_string(gl::NearPlane::Scene)),
                                              std::string(gl::to_string(gl::NearPlane::Tight))};
  return names;
}

const std::vector<std::string>& infinite_far_names() {
  static const std::vector<std::string> names{"exact", "epsilon", "doom3", "one-ulp"};
  return names;
}

MethodChoice method_choice(const std::string& names) {
  MethodChoice c;
  if (names == "all") {
    c.methods = methods_from("all", "--method");
    c.raytrace = true;
    c.policy = true;
    return c;
  }
  std::string rest;
  std::size_t start = 0;
  while (start <= names.size()) {
    const std::size_t comma = std::min(names.find(',', start), names.size());
    const std::string name = names.substr(start, comma - start);
    if (name == "policy")
      c.policy = true;
    else if (name == "raytrace")
      c.raytrace = true;
    else
      rest += (rest.empty() ? "" : ",") + name;
    start = comma + 1;
  }
  if (!rest.empty() || (!c.policy && !c.raytrace)) c.methods = methods_from(rest, "--method");
  return c;
}

nlohmann::json policy_occluders_json(const Scene& scene, const analysis::PolicyDecision& d) {
  nlohmann::json occluders = nlohmann::json::array();
  for (std::size_t o = 0; o < scene.objects.size(); ++o)
    if (scene.objects[o].occluder)
      occluders.push_back(
          {{"object", o}, {"method", std::string(to_string(d.object_methods[o]))}, {"why", d.reasons[o]}});
  return occluders;
}

std::vector<gl::ShadowMethod> methods_from(const std::string& names, const std::string& option) {
  if (names == "all") return {gl::kAllShadowMethods.begin(), gl::kAllShadowMethods.end()};
  std::vector<gl::ShadowMethod> methods;
  std::size_t start = 0;
  while (start <= names.size()) {
    const std::size_t comma = std::min(names.find(',', start), names.size());
    const std::string name = names.substr(start, comma - start);
    const auto m = gl::shadow_method_from_string(name);
    if (!m)
      throw Error(
          ErrorKind::Usage,
          option + " '" + name + "' is not one of zpass, zfail, zpplus, zpplus-corrected, preload, atomiczp (or all)");
    methods.push_back(*m);
    start = comma + 1;
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

// Spawns Python on the script; its stderr goes to `stderr_log` when not empty.
// Returns waitpid's raw status.
int spawn_python(const std::string& script, const std::vector<std::string>& args, const std::string& what,
                 const std::string& stderr_log) {
  const char* env = std::getenv("NEARCAP_PYTHON");
  const std::string py = env && *env ? env : (::access("/usr/bin/python3", X_OK) == 0 ? "/usr/bin/python3" : "python3");
  std::vector<std::string> all{py, script};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  ::posix_spawn_file_actions_init(&actions);
  if (!stderr_log.empty())
    ::posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, stderr_log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  pid_t pid = 0;
  const int spawned = ::posix_spawnp(&pid, py.c_str(), &actions, nullptr, argv.data(), environ);
  ::posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0)
    throw Error(ErrorKind::Io, py + ": cannot run Python for " + what + ": " + std::strerror(spawned) +
                                   " (scripts/install-deps.sh installs python3 and python3-matplotlib)");
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) throw Error(ErrorKind::Io, "waiting for " + what + ": " + std::string(std::strerror(errno)));
  return status;
}

}  // namespace

int run_python_script(const std::string& script, const std::vector<std::string>& args, const std::string& what) {
  const int status = spawn_python(script, args, what, "");
  return WIFEXITED(status) ? WEXITSTATUS(status) : 1;
}

int run_python_script_logged(const std::string& script, const std::vector<std::string>& args, const std::string& what,
                             const std::string& stderr_log) {
  return spawn_python(script, args, what, stderr_log);
}

}  // namespace nearcap::cli
