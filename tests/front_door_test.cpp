// The front door (nearcap/nearcap.hpp) and the library example built on it
// (examples/library_example.cpp, NEARCAP_LIBRARY_EXAMPLE): the example run on
// a bundled scene prints, line for line, what `nearcap cap`, `nearcap
// reference` and `nearcap cracks` say about that scene, so each front-door
// call is the command's composition of the layers; and the calls' own
// contracts (errors, the image size).
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_support.hpp"
#include "nearcap/nearcap.hpp"

namespace nearcap {
namespace {

namespace fs = std::filesystem;

// case_d: every method differs from the next on it (Z-pass wrong on most
// pixels, ZP+ corrected on its case-D pixels, the others right but one), so
// a call that drew or judged another method's frame prints another line.
const std::string kScene = "data/scenes/case_d.json";
const std::string kPolicy = "data/policy.json";

// The example's run, from the source directory (paths relative to it).
test::CliResult run_example(const std::string& args) {
  const fs::path dir = fs::temp_directory_path();
  const std::string stem = "nearcap_test_example_" + std::to_string(::getpid());
  const fs::path out = dir / (stem + ".out"), err = dir / (stem + ".err");
  const std::string command = "cd '" + std::string(NEARCAP_SOURCE_DIR) + "' && '" + NEARCAP_LIBRARY_EXAMPLE + "' " +
                              args + " > '" + out.string() + "' 2> '" + err.string() + "'";
  const int status = std::system(command.c_str());
  test::CliResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = test::slurp(out);
  r.err = test::slurp(err);
  fs::remove(out);
  fs::remove(err);
  return r;
}

nlohmann::json cli_json(const std::string& args) {
  const test::CliResult r = test::run_cli(args, "front_door");
  EXPECT_EQ(r.exit_code, 0) << "nearcap " << args << ": " << r.err;
  return nlohmann::json::parse(r.out);
}

std::string judged_line(const std::string& name, const nlohmann::json& record) {
  char line[256];
  std::snprintf(line, sizeof line, "%s: %zu wrong pixels of %zu seen, %zu cracks\n", name.c_str(),
                record.at("wrong").get<std::size_t>(), record.at("pixels_seen").get<std::size_t>(),
                record.at("cracks").get<std::size_t>());
  return line;
}

TEST(LibraryExample, PrintsWhatTheCommandsPrint) {
  // What the example must print, from the program's records of the same scene.
  std::string expected;
  const nlohmann::json cap = cli_json("cap " + kScene + " --light 0");
  expected += "near-cap: " + std::to_string(cap.at("faces").size()) + " faces, largest count " +
              std::to_string(cap.at("max_count").get<std::size_t>()) + "\n";
  const fs::path ref_dir = fs::temp_directory_path() / ("nearcap_test_front_door_" + std::to_string(::getpid()));
  const nlohmann::json ref = cli_json("reference " + kScene + " --light 0 --out '" + ref_dir.string() + "'");
  fs::remove_all(ref_dir);
  expected += "reference: " + std::to_string(ref.at("pixels_shadowed").get<std::size_t>()) + " pixels shadowed\n";
  const nlohmann::json cracks =
      cli_json("cracks " + kScene + " --light 0 --method zpass,zfail,zpplus,zpplus-corrected,preload");
  ASSERT_EQ(cracks.at("methods").size(), 5u);
  for (const nlohmann::json& r : cracks.at("methods")) expected += judged_line(r.at("method"), r);
  const nlohmann::json policy = cli_json("cracks " + kScene + " --light 0 --method policy --policy " + kPolicy);
  for (const nlohmann::json& o : policy.at("occluders"))
    expected += "object " + std::to_string(o.at("object").get<std::size_t>()) + ": " +
                o.at("method").get<std::string>() + " (" + o.at("why").get<std::string>() + ")\n";
  expected += judged_line("policy", policy);

  const test::CliResult example = run_example(kScene + " " + kPolicy);
  ASSERT_EQ(example.exit_code, 0) << example.err;
  EXPECT_EQ(example.out, expected);
  std::printf("%s", example.out.c_str());

  // docs/library.md shows this run's output.
  const std::string doc = test::slurp(std::string(NEARCAP_SOURCE_DIR) + "/docs/library.md");
  const std::string open = "<!-- output: library_example " + kScene + " " + kPolicy + " -->\n```\n",
                    close = "```\n<!-- end output -->";
  const auto begin = doc.find(open), end = doc.find(close, begin);
  ASSERT_TRUE(begin != std::string::npos && end != std::string::npos) << "docs/library.md lost its output markers";
  EXPECT_EQ(doc.substr(begin + open.size(), end - begin - open.size()), example.out)
      << "docs/library.md shows another output of the example: copy the one above into it";
}

TEST(LibraryExample, WithoutArgumentsSaysHowToRunIt) {
  const test::CliResult r = run_example("");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("usage: "), std::string::npos) << r.err;
  EXPECT_EQ(r.out, "");
}

TEST(LibraryExample, BadSceneIsOneErrorLine) {
  const test::CliResult r = run_example("data/scenes/no_such_scene.json " + kPolicy);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err.rfind("library_example: error (io): ", 0), 0u) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

// A bundled 320x240 scene with one light: the contract tests' frames are cheap.
Scene small_scene() { return load_scene(std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/far_grazing.json"); }

// The kind of the nearcap::Error that `call` throws ("usage", ...), or "none".
std::string kind_thrown(const std::function<void()>& call) {
  try {
    call();
  } catch (const Error& e) {
    return std::string(to_string(e.kind()));
  }
  return "none";
}

TEST(FrontDoor, ALightTheSceneLacksIsAUsageError) {
  const Scene scene = small_scene();
  ASSERT_EQ(scene.lights.size(), 1u);
  EXPECT_EQ(kind_thrown([&] { exact_near_cap(scene, 1); }), "usage");
  EXPECT_EQ(kind_thrown([&] { exact_reference(scene, 1); }), "usage");
  FrameSettings settings;
  settings.light = 1;
  EXPECT_EQ(kind_thrown([&] { judged_frame(scene, settings); }), "usage");
  const SwitchPolicy policy = load_policy(std::string(NEARCAP_SOURCE_DIR) + "/" + kPolicy);
  EXPECT_EQ(kind_thrown([&] { decide_policy(policy, scene, settings); }), "usage");
  EXPECT_EQ(kind_thrown([&] { judged_policy_frame(policy, scene, settings); }), "usage");
}

TEST(FrontDoor, ANegativeImageSizeIsAUsageError) {
  FrameSettings settings;
  settings.height = -1;
  EXPECT_EQ(kind_thrown([&] { emulation_settings(settings); }), "usage");
  EXPECT_EQ(kind_thrown([&] { judged_frame(small_scene(), settings); }), "usage");
}

TEST(FrontDoor, AnImageSizeOrAChoiceOutsideItsRangeIsAUsageError) {
  const Scene scene = small_scene();
  FrameSettings wide;
  wide.width = 16385;  // beyond the largest viewport a scene file may give
  EXPECT_EQ(kind_thrown([&] { judged_frame(scene, wide); }), "usage");
  FrameSettings method;
  method.method = static_cast<ShadowMethod>(99);
  EXPECT_EQ(kind_thrown([&] { judged_frame(scene, method); }), "usage");
  EXPECT_EQ(kind_thrown([&] { judged_frames(scene, {ShadowMethod::ZFail, static_cast<ShadowMethod>(-1)}); }), "usage");
  FrameSettings depth;
  depth.depth = static_cast<DepthFormat>(7);
  EXPECT_EQ(kind_thrown([&] { emulation_settings(depth); }), "usage");
  FrameSettings mapping;
  mapping.depth_mapping = static_cast<DepthMapping>(7);
  EXPECT_EQ(kind_thrown([&] { emulation_settings(mapping); }), "usage");
  FrameSettings projection;
  projection.light_projection = static_cast<LightProjection>(42);
  EXPECT_EQ(kind_thrown([&] { emulation_settings(projection); }), "usage");
}

// A Scene is a struct a program can edit after loading it: every call checks
// the fields a loaded scene has valid (check_scene_fields) and throws the
// kind load_scene would, instead of failing deep in the exact kernel.
TEST(FrontDoor, AnEditedSceneIsCheckedOnEntry) {
  const SwitchPolicy policy = load_policy(std::string(NEARCAP_SOURCE_DIR) + "/" + kPolicy);
  const struct {
    const char* edit;
    std::function<void(Scene&)> apply;
    const char* kind;
  } cases[] = {
      {"a light at NaN", [](Scene& s) { s.lights[0].position.x = std::nan(""); }, "non-finite"},
      {"no mesh", [](Scene& s) { s.objects[0].mesh = nullptr; }, "schema"},
      {"a flat frustum", [](Scene& s) { s.camera.frustum.left = s.camera.frustum.right; }, "camera"},
      {"a negative width", [](Scene& s) { s.camera.width = -5; }, "camera"},
      {"an infinite transform",
       [](Scene& s) { s.objects[0].object_to_world.rows[0][3] = std::numeric_limits<double>::infinity(); },
       "non-finite"},
      {"a singular transform",
       [](Scene& s) {
         s.objects[0].object_to_world.rows[1] = {0, 0, 0, 0};
       },
       "schema"},
      {"no light", [](Scene& s) { s.lights.clear(); }, "schema"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.edit);
    Scene scene = small_scene();
    c.apply(scene);
    EXPECT_EQ(kind_thrown([&] { exact_near_cap(scene, 0); }), c.kind);
    EXPECT_EQ(kind_thrown([&] { exact_reference(scene, 0); }), c.kind);
    EXPECT_EQ(kind_thrown([&] { judged_frame(scene); }), c.kind);
    EXPECT_EQ(kind_thrown([&] { decide_policy(policy, scene); }), c.kind);
    EXPECT_EQ(kind_thrown([&] { judged_policy_frame(policy, scene); }), c.kind);
  }
}

// Memory that runs out is Error(Resource), as on the command line, not
// std::bad_alloc: a 16384 x 16384 frame (gigabytes) under a 2 GB address
// space.  In a process of its own (this test binary run again for this test
// alone: a fork of a process whose TBB workers run may hang), not under
// AddressSanitizer, whose allocator needs the address space itself.
#if defined(__SANITIZE_ADDRESS__)
#define NEARCAP_TEST_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define NEARCAP_TEST_ASAN 1
#endif
#endif
TEST(FrontDoor, MemoryThatRunsOutIsAResourceError) {
#ifdef NEARCAP_TEST_ASAN
  GTEST_SKIP() << "AddressSanitizer reserves the address space this test limits";
#else
  if (std::getenv("NEARCAP_FRONT_DOOR_MEMORY_CHILD") != nullptr) {
    const rlimit limit{rlim_t{2} << 30, rlim_t{2} << 30};
    if (::setrlimit(RLIMIT_AS, &limit) != 0) ::_exit(3);
    FrameSettings settings;
    settings.method = ShadowMethod::ZFail;
    settings.width = settings.height = 16384;
    try {
      (void)judged_frame(small_scene(), settings);
    } catch (const Error& e) {
      ::_exit(e.kind() == ErrorKind::Resource ? 0 : 1);
    } catch (...) {
      ::_exit(2);  // std::bad_alloc, say
    }
    ::_exit(4);  // it fitted
  }
  const std::string self = fs::read_symlink("/proc/self/exe").string();
  const int status = std::system(("NEARCAP_FRONT_DOOR_MEMORY_CHILD=1 '" + self +
                                  "' --gtest_filter=FrontDoor.MemoryThatRunsOutIsAResourceError > /dev/null 2>&1")
                                     .c_str());
  ASSERT_TRUE(WIFEXITED(status)) << "the child ended by signal " << (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
  EXPECT_EQ(WEXITSTATUS(status), 0) << "1: another Error kind, 2: not an Error, 3: no limit, 4: no failure";
#endif
}

TEST(FrontDoor, TheFrameHasTheSettingsImageSizeAndMethod) {
  const Scene scene = small_scene();
  FrameSettings settings;
  settings.method = ShadowMethod::ZFail;
  settings.width = 40;  // the height stays the camera's
  const JudgedFrame j = judged_frame(scene, settings);
  EXPECT_EQ(j.frame.method, ShadowMethod::ZFail);
  EXPECT_EQ(j.report.method, "zfail");
  EXPECT_EQ(j.frame.width, 40);
  EXPECT_EQ(j.frame.height, scene.camera.height);
  EXPECT_EQ(j.report.verdict.size(), static_cast<std::size_t>(40 * scene.camera.height));
  ASSERT_TRUE(j.report.cracks.has_value());  // the crack distances were measured
  EXPECT_LE(*j.report.cracks, j.report.wrong);
}

TEST(FrontDoor, EmulationSettingsCarryTheChoices) {
  FrameSettings settings;
  settings.depth = DepthFormat::Float32;
  settings.depth_mapping = DepthMapping::Reversed;
  settings.light_projection = LightProjection::ClippedSides;
  const gl::EmulationSettings s = emulation_settings(settings);
  EXPECT_EQ(s.depth, DepthFormat::Float32);
  EXPECT_EQ(s.depth_mapping, DepthMapping::Reversed);
  EXPECT_EQ(s.light_frustum.projection, LightProjection::ClippedSides);
}

}  // namespace
}  // namespace nearcap
