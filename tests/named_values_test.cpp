// The tables of named choices (nearcap/named_values.hpp): every table
// round-trips name -> value -> name, the names files and scripts use stay
// spelled as they are, and the command line's help and errors list every
// name of the table they come from.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cli_support.hpp"
#include "nearcap/analysis/engine_policies.hpp"
#include "nearcap/analysis/hard_case_sampler.hpp"
#include "nearcap/gl/float_transforms.hpp"
#include "nearcap/gl/light_frustum.hpp"
#include "nearcap/gl/pipeline.hpp"
#include "nearcap/gl/rasterizer.hpp"
#include "nearcap/gl/shadow_methods.hpp"
#include "nearcap/gl/tight_near_plane.hpp"
#include "nearcap/named_values.hpp"
#include "nearcap/raytrace/shadow_ray_tracer.hpp"
#include "nearcap/render/glsl_shadow_programs.hpp"

namespace nearcap {
namespace test_choices {

enum class Fruit { Apple, Pear, Plum };
inline constexpr NamedValue<Fruit> kFruitTable[] = {
    {Fruit::Pear, "pear", ""},
    {Fruit::Apple, "apple", "red or green"},
    {Fruit::Plum, "plum", "blue"},
};
constexpr const auto& named_values(Fruit) { return kFruitTable; }

enum class Twice { A, B };
inline constexpr NamedValue<Twice> kTwiceTable[] = {{Twice::A, "a", ""}, {Twice::B, "a", ""}};
constexpr const auto& named_values(Twice) { return kTwiceTable; }

}  // namespace test_choices

namespace {

using test_choices::Fruit;

TEST(NamedValues, LookUpByNameAndByValue) {
  EXPECT_EQ(name_of(Fruit::Apple), "apple");
  EXPECT_EQ(name_of(static_cast<Fruit>(7)), "?");
  EXPECT_EQ(value_named<Fruit>("plum"), Fruit::Plum);
  // Whole names, case-sensitive: no prefix, no other case, no padding.
  EXPECT_FALSE(value_named<Fruit>("Plum").has_value());
  EXPECT_FALSE(value_named<Fruit>("plu").has_value());
  EXPECT_FALSE(value_named<Fruit>("plum ").has_value());
  EXPECT_FALSE(value_named<Fruit>("").has_value());
}

TEST(NamedValues, ListsFollowTheTablesOrder) {
  EXPECT_EQ(named_count<Fruit>(), 3u);
  EXPECT_EQ(names_of<Fruit>(), (std::vector<std::string>{"pear", "apple", "plum"}));
  EXPECT_EQ(values_of<Fruit>(), (std::array<Fruit, 3>{Fruit::Pear, Fruit::Apple, Fruit::Plum}));
  EXPECT_EQ(names_joined<Fruit>(), "pear, apple, plum");
  EXPECT_EQ(names_joined<Fruit>(" or "), "pear, apple or plum");
  EXPECT_EQ(values_described<Fruit>(), "pear, apple (red or green) or plum (blue)");
  EXPECT_EQ(values_described<Fruit>(", "), "pear, apple (red or green), plum (blue)");
}

TEST(NamedValues, ATableWithANameTwiceIsNotUnique) {
  EXPECT_TRUE(names_are_unique<Fruit>());
  EXPECT_FALSE(names_are_unique<test_choices::Twice>());
}

// name -> value -> name for every entry, and value -> name -> value; the
// table's own to_string and *_from_string agree with it.
template <class E, class ToString, class FromString>
void expect_round_trip(ToString to_string_fn, FromString from_string_fn) {
  EXPECT_TRUE(names_are_unique<E>());
  for (const NamedValue<E>& v : table_of<E>()) {
    SCOPED_TRACE(std::string(v.name));
    ASSERT_EQ(value_named<E>(v.name), v.value);
    EXPECT_EQ(name_of(*value_named<E>(v.name)), v.name);
    EXPECT_EQ(to_string_fn(v.value), v.name);
    EXPECT_EQ(from_string_fn(v.name), std::optional<E>(v.value));
  }
  EXPECT_FALSE(from_string_fn("no-such-name").has_value());
}

template <class E>
void expect_round_trip() {
  expect_round_trip<E>([](E e) { return name_of(e); }, [](std::string_view n) { return value_named<E>(n); });
}

TEST(NamedValues, EveryTableRoundTrips) {
  expect_round_trip<gl::ShadowMethod>([](gl::ShadowMethod m) { return gl::to_string(m); },
                                      gl::shadow_method_from_string);
  expect_round_trip<gl::ZFailFar>([](gl::ZFailFar f) { return gl::to_string(f); }, gl::zfail_far_from_string);
  expect_round_trip<gl::SwitchClamp>([](gl::SwitchClamp c) { return gl::to_string(c); }, gl::switch_clamp_from_string);
  expect_round_trip<gl::ZPassFar>([](gl::ZPassFar f) { return gl::to_string(f); }, gl::zpass_far_from_string);
  expect_round_trip<gl::VolumeCulling>([](gl::VolumeCulling c) { return gl::to_string(c); },
                                       gl::volume_culling_from_string);
  expect_round_trip<gl::DepthMapping>([](gl::DepthMapping m) { return gl::to_string(m); },
                                      gl::depth_mapping_from_string);
  expect_round_trip<gl::InfiniteFar>([](gl::InfiniteFar f) { return gl::to_string(f); }, gl::infinite_far_from_string);
  expect_round_trip<gl::LightProjection>([](gl::LightProjection p) { return gl::to_string(p); },
                                         gl::light_projection_from_string);
  expect_round_trip<gl::LightNearRule>([](gl::LightNearRule r) { return gl::to_string(r); },
                                       gl::light_near_rule_from_string);
  expect_round_trip<gl::NearPlane>([](gl::NearPlane p) { return gl::to_string(p); }, gl::near_plane_from_string);
  expect_round_trip<gl::DepthFormat>([](gl::DepthFormat f) { return gl::to_string(f); },
                                     [](std::string_view n) { return value_named<gl::DepthFormat>(n); });
  expect_round_trip<gl::FillRule>();
  expect_round_trip<gl::ViewportArithmetic>();
  expect_round_trip<gl::DepthInterpolation>();
  expect_round_trip<gl::ClipperArithmetic>();
  expect_round_trip<raytrace::ShadowEpsilon>([](raytrace::ShadowEpsilon e) { return raytrace::to_string(e); },
                                             raytrace::shadow_epsilon_from_string);
  expect_round_trip<render::VertexStage>([](render::VertexStage s) { return render::to_string(s); },
                                         render::vertex_stage_from_string);
  expect_round_trip<analysis::EnginePolicy>([](analysis::EnginePolicy p) { return analysis::to_string(p); },
                                            analysis::engine_policy_from_string);
  expect_round_trip<analysis::HardCaseKind>(
      [](analysis::HardCaseKind k) { return analysis::to_string(k); },
      [](std::string_view n) { return std::optional<analysis::HardCaseKind>(value_named<analysis::HardCaseKind>(n)); });
}

// The spellings users' files, scripts and policies hold: a table may gain a
// name, never rename or drop one (compared as sets: the order is the help's).
template <class E>
void expect_names(std::vector<std::string> expected) {
  std::vector<std::string> names = names_of<E>();
  std::sort(names.begin(), names.end());
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(names, expected);
}

TEST(NamedValues, NamesStaySpelledAsFilesHoldThem) {
  expect_names<gl::ShadowMethod>({"zpass", "zfail", "zpplus", "zpplus-corrected", "preload", "atomiczp"});
  expect_names<gl::ZFailFar>({"infinite", "clamp", "clamp-far", "far-cap"});
  expect_names<gl::SwitchClamp>({"clamp", "clamp-far", "far-cap"});
  expect_names<gl::ZPassFar>({"finite", "infinite"});
  expect_names<gl::VolumeCulling>({"none", "scissor", "depth-bounds", "both"});
  expect_names<gl::DepthMapping>({"standard", "reversed"});
  expect_names<gl::InfiniteFar>({"exact", "epsilon", "doom3", "one-ulp"});
  expect_names<gl::LightProjection>({"paper", "glfrustum", "composed", "rebased", "clipped-sides"});
  expect_names<gl::LightNearRule>({"paper-ratio", "exact-max", "near-clamp"});
  expect_names<gl::NearPlane>({"scene", "tight"});
  expect_names<gl::DepthFormat>({"fixed24", "float32"});
  expect_names<gl::FillRule>({"top-left", "bottom-left"});
  expect_names<gl::ViewportArithmetic>({"divide", "llvmpipe"});
  expect_names<gl::DepthInterpolation>({"exact", "llvmpipe"});
  expect_names<gl::ClipperArithmetic>({"inside", "mesa"});
  expect_names<raytrace::ShadowEpsilon>({"fixed", "relative", "primitive-id"});
  expect_names<render::VertexStage>({"recorded", "glsl"});
  expect_names<analysis::EnginePolicy>({"doom3", "doom3-bfg", "ogre", "always-zfail"});
  expect_names<analysis::HardCaseKind>({"light-near-plane", "light-in-near-plane", "grazing", "eye-in-shadow",
                                        "far-from-origin", "tiny-near", "straddling", "several-occluders",
                                        "several-lights", "real-mesh", "eye-near-volume", "far-light"});
}

TEST(NamedValues, SwitchClampIsNamedAsTheZFailFarItIs) {
  for (gl::SwitchClamp c : values_of<gl::SwitchClamp>()) EXPECT_EQ(name_of(c), name_of(gl::as_zfail_far(c)));
}

TEST(NamedValues, EveryShadowMethodIsInAllAndInTheTablesOrder) {
  EXPECT_EQ(gl::kAllShadowMethods, values_of<gl::ShadowMethod>());
  EXPECT_EQ(analysis::kAllEnginePolicies, values_of<analysis::EnginePolicy>());
}

// The help sentence of `flag` in `help`: from the flag to the next option's
// line, without CLI11's list of accepted values (":{a,b}"), so that the
// sentence itself must name every value.
std::string option_help(const std::string& help, const std::string& flag) {
  const std::size_t at = help.find("  " + flag + " ");
  if (at == std::string::npos) return "";
  const std::size_t end = help.find("\n  -", at + 1);
  std::string text = help.substr(at, end == std::string::npos ? std::string::npos : end - at);
  const std::size_t open = text.find(":{"), close = text.find('}');
  if (open != std::string::npos && close != std::string::npos && open < close) text.erase(open, close + 1 - open);
  return text;
}

template <class E>
void expect_help_lists_every_name(const std::string& help, const std::string& flag) {
  const std::string text = option_help(help, flag);
  ASSERT_FALSE(text.empty()) << flag << " is not in the help:\n" << help;
  for (const NamedValue<E>& v : table_of<E>())
    EXPECT_NE(text.find(std::string(v.name)), std::string::npos) << flag << "'s help does not name " << v.name << ":\n"
                                                                 << text;
}

TEST(NamedValues, TheHelpListsEveryName) {
  const test::CliResult cracks = test::run_cli("cracks --help", "named_cracks");
  ASSERT_EQ(cracks.exit_code, 0) << cracks.err;
  const std::string& h = cracks.out;
  expect_help_lists_every_name<gl::DepthFormat>(h, "--depth");
  expect_help_lists_every_name<gl::FillRule>(h, "--fill-rule");
  expect_help_lists_every_name<gl::ViewportArithmetic>(h, "--viewport");
  expect_help_lists_every_name<gl::DepthInterpolation>(h, "--depth-interpolation");
  expect_help_lists_every_name<gl::ClipperArithmetic>(h, "--clipper");
  expect_help_lists_every_name<gl::LightProjection>(h, "--light-projection");
  expect_help_lists_every_name<gl::LightNearRule>(h, "--l-near");
  expect_help_lists_every_name<gl::ZFailFar>(h, "--zfail-far");
  expect_help_lists_every_name<gl::SwitchClamp>(h, "--switch-clamp");
  expect_help_lists_every_name<gl::ZPassFar>(h, "--zpass-far");
  expect_help_lists_every_name<gl::InfiniteFar>(h, "--infinite-far");
  expect_help_lists_every_name<gl::DepthMapping>(h, "--depth-mapping");
  expect_help_lists_every_name<gl::NearPlane>(h, "--near-plane");
  expect_help_lists_every_name<gl::VolumeCulling>(h, "--volume-culling");
  expect_help_lists_every_name<gl::ShadowMethod>(h, "--method");
  expect_help_lists_every_name<raytrace::ShadowEpsilon>(h, "--shadow-epsilon");

  const test::CliResult sweep = test::run_cli("sweep --help", "named_sweep");
  ASSERT_EQ(sweep.exit_code, 0) << sweep.err;
  expect_help_lists_every_name<analysis::EnginePolicy>(sweep.out, "--policies");
  expect_help_lists_every_name<analysis::HardCaseKind>(sweep.out, "--kinds");
  expect_help_lists_every_name<gl::VolumeCulling>(sweep.out, "--volume-culling");

  const test::CliResult tune = test::run_cli("tune --help", "named_tune");
  ASSERT_EQ(tune.exit_code, 0) << tune.err;
  expect_help_lists_every_name<gl::LightProjection>(tune.out, "--light-projection");
  expect_help_lists_every_name<gl::DepthFormat>(tune.out, "--depth");
  expect_help_lists_every_name<gl::DepthMapping>(tune.out, "--depth-mapping");
  expect_help_lists_every_name<gl::NearPlane>(tune.out, "--near-plane");
}

// A variant spec with a bad value is refused with every name of the choice's
// table (with_variant reads the same tables as the options).
template <class E>
void expect_variant_error_lists_every_name(const std::string& option) {
  const test::CliResult r = test::run_cli(
      "sweep --samples 1 --variant " + option + "=no-such-name --out /nonexistent/s.csv", "named_variant");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "nearcap: error (usage): --variant '" + option + "=no-such-name': " + option +
                       " 'no-such-name' is not one of " + names_joined<E>() + " (see nearcap sweep --help)\n");
}

TEST(NamedValues, AVariantsBadValueNamesEveryValue) {
  expect_variant_error_lists_every_name<gl::DepthFormat>("depth");
  expect_variant_error_lists_every_name<gl::ClipperArithmetic>("clipper");
  expect_variant_error_lists_every_name<gl::LightProjection>("light-projection");
  expect_variant_error_lists_every_name<gl::SwitchClamp>("switch-clamp");
  expect_variant_error_lists_every_name<gl::VolumeCulling>("volume-culling");
}

}  // namespace
}  // namespace nearcap
