// The command line's values, checked before anything runs.  Every integer
// option of every subcommand, read from the program's own --help: negative,
// overflowing, non-decimal and out-of-range values are one-line usage errors
// naming the option, and nothing is written.  And file names that are not
// UTF-8 (a file name is bytes, JSON text is UTF-8): the outputs are written
// under their real names, the JSON names them with U+FFFD.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "cli_support.hpp"

namespace nearcap {
namespace {

namespace fs = std::filesystem;

class CliValidation : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("nearcap_cli_validation_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "out");
    for (const char* mesh : {"box.off", "ground.off"})
      fs::copy_file(fs::path(NEARCAP_SOURCE_DIR) / "data/meshes" / mesh, dir_ / mesh);
    // A box over the ground, 64 x 48.
    std::ofstream(dir_ / "B.json") << R"({"camera":{"eye":[0,2.5,5],"target":[0,0.7,0],"up":[0,1,0],
      "fovy_deg":50,"near":0.1,"far":100,"width":64,"height":48},"lights":[{"position":[2,5,1.5]}],
      "objects":[{"mesh":"box.off","translate":[0,1,0]},{"mesh":"ground.off","occluder":false}]})";
    write_path(dir_ / "P.json", 2);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // A bundled camera path, `frames` frames long, its base scene named absolutely.
  static void write_path(const fs::path& file, int frames) {
    const fs::path data = fs::path(NEARCAP_SOURCE_DIR) / "data";
    nlohmann::json path = nlohmann::json::parse(test::slurp(data / "paths/near_plane_sweep.json"));
    path["scene"] = (data / "scenes/room_side_light.json").string();
    path["frames"] = frames;
    path["width"] = 32;
    path["height"] = 24;
    std::ofstream(file) << path.dump();
  }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  test::CliResult run(const std::string& args) const { return test::run_cli(args, "validation", test::kHangBound); }
  std::vector<std::string> written() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir_ / "out")) names.push_back(e.path().filename().string());
    return names;
  }

  fs::path dir_;
};

// The integer options a subcommand's --help lists: "--name INT..." or "--name UINT...".
std::vector<std::string> integer_options(const std::string& help) {
  std::vector<std::string> names;
  std::istringstream lines(help);
  std::string line;
  while (std::getline(lines, line)) {
    std::istringstream words(line);
    std::string name, type;
    words >> name >> type;
    if (name.rfind("--", 0) == 0 && (type.rfind("INT", 0) == 0 || type.rfind("UINT", 0) == 0)) names.push_back(name);
  }
  return names;
}

// Each subcommand with arguments it would run with: (option, value) pairs, an
// empty option for a positional argument.  OUT is the output folder.
using Arguments = std::vector<std::pair<std::string, std::string>>;

std::map<std::string, Arguments> runnable_commands(const std::string& dir) {
  const std::string out = dir + "/out";
  return {
      {"classify", {{"", dir + "/B.json"}}},
      {"cap", {{"", dir + "/B.json"}, {"--light", "0"}, {"--out", out + "/cap.json"}}},
      {"reference", {{"", dir + "/B.json"}, {"--light", "0"}, {"--out", out + "/reference"}}},
      {"cracks", {{"", dir + "/B.json"}, {"--light", "0"}, {"--method", "zfail"}, {"--out", out + "/cracks"}}},
      {"frame", {{"", dir + "/P.json"}, {"--frame", "0"}, {"--out", out + "/frame.json"}}},
      {"sample", {{"--index", "0"}, {"--out", out + "/sample.json"}}},
      {"sweep", {{"--samples", "1"}, {"--methods", "zfail"}, {"--out", out + "/sweep.csv"}}},
      {"report", {{"", dir + "/none.csv"}, {"--out", out + "/report"}}},
      {"tune", {{"", dir + "/none.csv"}, {"--out", out + "/policy.json"}}},
      {"fit-l-near", {{"--samples", "10"}, {"--out", out + "/fit.json"}}},
      {"render", {{"", dir + "/B.json"}, {"--out", out + "/render"}}},
      {"view", {{"", dir + "/B.json"}, {"--out", out + "/view"}}},
      {"evaluate", {{"--samples", "1"}, {"--width", "8"}, {"--height", "6"}, {"--out", out + "/evaluate"}}},
  };
}

// `base` with `option` given `value` (replaced where base has it).
std::string command_line(const std::string& sub, Arguments base, const std::string& option, const std::string& value) {
  const auto at = std::find_if(base.begin(), base.end(), [&](const auto& a) { return a.first == option; });
  if (at != base.end())
    at->second = value;
  else
    base.push_back({option, value});
  std::string line = sub;
  for (const auto& [name, v] : base) line += (name.empty() ? "" : " " + name) + " '" + v + "'";
  return line;
}

TEST_F(CliValidation, EveryIntegerOptionRefusesNegativeOverflowingAndNonDecimalValues) {
  const auto commands = runnable_commands(dir_.string());
  std::set<std::string> found;
  for (const auto& [sub, base] : commands) {
    const test::CliResult help = run(sub + " --help");
    if (help.exit_code != 0 && (sub == "render" || sub == "view" || sub == "evaluate"))
      continue;  // built without the real GL
    ASSERT_EQ(help.exit_code, 0) << sub << "\n" << help.err;
    for (const std::string& option : integer_options(help.out)) {
      found.insert(sub + " " + option);
      // 2^64 and past: strtoull saturates at 2^64 - 1 and unsigned conversion wraps "-1".
      for (const char* value : {"-5", "-1", "18446744073709551616", "99999999999999999999999", "1e30", "0x10"}) {
        const std::string args = command_line(sub, base, option, value);
        SCOPED_TRACE(args);
        const test::CliResult r = run(args);
        EXPECT_EQ(r.exit_code, 2) << r.err;
        EXPECT_EQ(r.err.rfind("nearcap: error (usage): " + option + ":", 0), 0u) << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_TRUE(r.out.empty()) << r.out;
        EXPECT_TRUE(written().empty()) << written().front();
      }
    }
  }
  // The table reads the options from --help: it must find them all.
  for (const char* expected :
       {"cap --light",          "reference --light", "cracks --light",     "cracks --subpixel-bits",
        "frame --frame",        "frame --width",     "frame --height",     "sample --seed",
        "sample --width",       "sample --height",   "sample --index",     "sweep --samples",
        "sweep --seed",         "sweep --width",     "sweep --height",     "sweep --subpixel-bits",
        "fit-l-near --samples", "fit-l-near --seed", "fit-l-near --width", "fit-l-near --height"})
    EXPECT_TRUE(found.count(expected)) << expected << " not found among the integer options of --help";
}

TEST_F(CliValidation, ValuesPastEachOptionsRangeAreUsageErrors) {
  const auto commands = runnable_commands(dir_.string());
  const std::vector<std::pair<std::string, std::string>> cases = {{"sweep --width", "0"},
                                                                  {"sweep --width", "-4"},
                                                                  {"sweep --height", "0"},
                                                                  {"sweep --width", "16385"},
                                                                  {"sweep --samples", "100000001"},
                                                                  {"sample --width", "0"},
                                                                  {"sample --height", "1000000000"},
                                                                  {"frame --width", "0"},
                                                                  {"frame --frame", "2147483648"},
                                                                  {"cracks --subpixel-bits", "13"},
                                                                  {"fit-l-near --samples", "0"},
                                                                  {"fit-l-near --samples", "100001"}};
  for (const auto& [which, value] : cases) {
    const std::string sub = which.substr(0, which.find(' ')), option = which.substr(which.find(' ') + 1);
    const std::string args = command_line(sub, commands.at(sub), option, value);
    SCOPED_TRACE(args);
    const test::CliResult r = run(args);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(r.err.rfind("nearcap: error (usage): " + option + ": '" + value + "' is", 0), 0u) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_TRUE(written().empty()) << written().front();
  }
}

TEST_F(CliValidation, ValuesInRangeAreReadInDecimal) {
  // The largest index, and a leading zero that is not octal.
  const test::CliResult r =
      run("sample --index 18446744073709551615 --seed 18446744073709551615 --width 010 --height 8");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json scene = nlohmann::json::parse(r.out);
  EXPECT_EQ(scene["camera"]["width"], 10);
  const test::CliResult sweep =
      run("sweep --samples 2 --width 16 --height 012 --methods zfail --out " + path("out/sweep.csv") + " --seed 3");
  ASSERT_EQ(sweep.exit_code, 0) << sweep.err;
  const std::string csv = test::slurp(path("out/sweep.csv"));
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 3) << csv;
  EXPECT_NE(csv.find("--width 16 --height 12"), std::string::npos) << csv;
}

TEST_F(CliValidation, NonFiniteFloatOptionsAreUsageErrors) {
  for (const char* args : {"cracks B.json --light 0 --guard-band inf", "cracks B.json --light 0 --l-near-scale nan",
                           "cracks B.json --light 0 --max-memory 1e999",
                           "reference B.json --light 0 --out out/r "
                           "--max-memory inf"}) {
    SCOPED_TRACE(args);
    const test::CliResult r = test::run_cli(std::string(args), "validation", "cd '" + dir_.string() + "' && ");
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(r.err.rfind("nearcap: error (usage): --", 0), 0u) << r.err;
    EXPECT_NE(r.err.find("is not a finite number"), std::string::npos) << r.err;
    EXPECT_TRUE(written().empty()) << written().front();
  }
}

// A guard band past float32's range reads as infinity: refused, not run as
// "inf" (inf times a zero w is no distance).
TEST_F(CliValidation, AGuardBandBeyondFloat32IsRefused) {
  const test::CliResult r =
      test::run_cli("cracks B.json --light 0 --guard-band 1e300", "validation", "cd '" + dir_.string() + "' && ");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(r.err.rfind("nearcap: error (usage): --guard-band must be at least 1", 0), 0u) << r.err;
  EXPECT_NE(r.err.find("a finite float32"), std::string::npos) << r.err;
}

TEST_F(CliValidation, AValueBelowTheDoublesRangeIsFiniteAndAZeroMemoryLimitIsNamedAsSuch) {
  // 1e-310 is a subnormal double: finite; --max-memory must be above 0.
  const test::CliResult r = test::run_cli("cracks B.json --light 0 --method zpass --l-near-scale 1e-310", "validation",
                                          "cd '" + dir_.string() + "' && ");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  const test::CliResult zero =
      test::run_cli("cracks B.json --light 0 --max-memory 0", "validation", "cd '" + dir_.string() + "' && ");
  EXPECT_EQ(zero.exit_code, 2);
  EXPECT_EQ(zero.err, "nearcap: error (usage): --max-memory: '0' is not above 0 (GB) (see nearcap cracks --help)\n");
}

TEST_F(CliValidation, ASweepTooLargeForTheMachineIsRefusedBeforeItsCsvExists) {
  const test::CliResult r = test::run_cli(
      "sweep --samples 1 --width 16384 --height 16384 --methods zpass --max-memory 4 --out " + path("big.csv"),
      "validation", "timeout 60");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(r.err.rfind("nearcap: error (resource): the sampled configurations: sweep (", 0), 0u) << r.err;
  EXPECT_NE(r.err.find("at 16384x16384 needs about"), std::string::npos) << r.err;
  for (const auto& e : fs::directory_iterator(dir_))
    EXPECT_NE(e.path().filename().string().rfind("big.csv", 0), 0u) << e.path();
  // One configuration is computed once, whatever the cores: 64 MB + 120 bytes x 1024 x 1024 fits 0.2 GB.
  const test::CliResult one = test::run_cli(
      "sweep --samples 1 --width 1024 --height 1024 --methods zpass "
      "--max-memory 0.2 --out " +
          path("one.csv"),
      "validation", "timeout 300");
  EXPECT_EQ(one.exit_code, 0) << one.err;
}

// ---- file names that are not UTF-8 ---------------------------------------

const std::string kReplacement = "\xEF\xBF\xBD";  // U+FFFD in UTF-8

TEST_F(CliValidation, FrameOfAPathWhoseNameIsNotUtf8) {
  write_path(dir_ / "\xff.json", 2);
  const test::CliResult r = run("frame '" + path("\xff.json") + "' --frame 1");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_TRUE(nlohmann::json::accept(r.out)) << r.out;
  EXPECT_NE(nlohmann::json::parse(r.out)["description"].get<std::string>().find(kReplacement), std::string::npos);
  const test::CliResult to_file =
      run("frame '" + path("\xff.json") + "' --frame 1 --out '" + path("out/\xfe.json") + "'");
  ASSERT_EQ(to_file.exit_code, 0) << to_file.err;
  EXPECT_EQ(test::slurp(path("out/\xfe.json")), r.out);
}

TEST_F(CliValidation, ReferenceCracksAndCapOfASceneWhoseNameIsNotUtf8) {
  fs::copy_file(dir_ / "B.json", dir_ / "\xfd.json");
  const std::string scene = "'" + path("\xfd.json") + "' --light 0";
  const test::CliResult reference = run("reference " + scene + " --out '" + path("out/r\xfc") + "'");
  ASSERT_EQ(reference.exit_code, 0) << reference.err;
  EXPECT_TRUE(nlohmann::json::accept(test::slurp(path("out/r\xfc/reference.json"))));
  EXPECT_TRUE(nlohmann::json::accept(reference.out)) << reference.out;

  const test::CliResult cracks = run("cracks " + scene + " --method zfail --out '" + path("out/k\xfb") + "'");
  ASSERT_EQ(cracks.exit_code, 0) << cracks.err;
  EXPECT_TRUE(nlohmann::json::accept(test::slurp(path("out/k\xfb/cracks.json"))));

  const test::CliResult cap =
      run("cap " + scene + " --out '" + path("out/c\xfa.json") + "' --svg '" + path("out/c\xfa.svg") + "'");
  ASSERT_EQ(cap.exit_code, 0) << cap.err;
  const std::string json = test::slurp(path("out/c\xfa.json"));
  ASSERT_TRUE(nlohmann::json::accept(json)) << json;
  EXPECT_NE(json.find(kReplacement), std::string::npos) << json;
  EXPECT_TRUE(fs::is_regular_file(path("out/c\xfa.svg")));
}

TEST_F(CliValidation, SweepOfAPathWhoseNameIsNotUtf8) {
  // A path's name goes into the rows (configuration, source, replay), which
  // tune and report read as UTF-8: refused, nothing written.
  write_path(dir_ / "\xff.json", 2);
  const test::CliResult refused =
      run("sweep --path '" + path("\xff.json") + "' --methods zfail --out '" + path("out/p.csv") + "'");
  EXPECT_EQ(refused.exit_code, 2) << refused.err;
  EXPECT_NE(refused.err.find("is not UTF-8 text, or holds a control character"), std::string::npos) << refused.err;
  EXPECT_TRUE(written().empty()) << written().front();
  // The CSV's own name is no field: one that is not UTF-8 is written, its
  // sidecar stores it with U+FFFD, and the sweep resumes with the options it
  // was made with (nothing left to run, the rows unchanged).
  write_path(dir_ / "p.json", 2);
  const std::string sweep =
      "sweep --path '" + path("p.json") + "' --methods zfail --out '" + path("out/\xf0.csv") + "'";
  const test::CliResult r = run(sweep);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string csv = test::slurp(path("out/\xf0.csv"));
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 3) << csv;
  ASSERT_TRUE(nlohmann::json::accept(test::slurp(path("out/\xf0.csv.meta.json"))));
  const test::CliResult resumed = run(sweep + " --resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_EQ(test::slurp(path("out/\xf0.csv")), csv);
}

TEST_F(CliValidation, AMeshFolderJsonCannotNameIsOneIoError) {
  // The frame's scene names its meshes absolutely: under a folder whose name
  // is not UTF-8 it cannot, and says so before writing anything.
  fs::create_directories(dir_ / "d\xff");
  fs::copy_file(dir_ / "B.json", dir_ / "d\xff/B.json");
  for (const char* mesh : {"box.off", "ground.off"}) fs::copy_file(dir_ / mesh, dir_ / "d\xff" / mesh);
  nlohmann::json p = nlohmann::json::parse(test::slurp(dir_ / "P.json"));
  p["scene"] = "B.json";
  std::ofstream(dir_ / "d\xff/P.json") << p.dump();
  // (sweep refuses the path's name before it reads the path.)
  for (const auto& [args, kind] :
       {std::pair<std::string, std::string>{
            "frame '" + path("d\xff/P.json") + "' --frame 0 --out '" + path("out/f.json") + "'", "io"},
        {"sweep --path '" + path("d\xff/P.json") + "' --out '" + path("out/s.csv") + "'", "usage"}}) {
    SCOPED_TRACE(args);
    const test::CliResult r = run(args);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(r.err.rfind("nearcap: error (" + kind + "): ", 0), 0u) << r.err;
    EXPECT_NE(r.err.find("not UTF-8"), std::string::npos) << r.err;
    // A usage mistake names the command's help page; an io error does not.
    const std::string command = args.substr(0, args.find(' '));
    EXPECT_EQ(r.err.find("(see nearcap " + command + " --help)\n") != std::string::npos, kind == "usage") << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_TRUE(written().empty()) << written().front();
  }
}

// render's lit frames and view draw every light unless --light K names one:
// a K the scene does not have is a usage error there too, before any GL.
TEST_F(CliValidation, AnOptionalLightOutOfRangeIsAUsageError) {
  const std::string scene = "'" + (dir_ / "B.json").string() + "'";
  const test::CliResult render = run("render " + scene + " --light 1 --out '" + (dir_ / "out/r").string() + "'");
  EXPECT_EQ(render.exit_code, 2) << render.err;
  EXPECT_NE(render.err.find("--light 1 is out of range (the scene has 1 light(s))"), std::string::npos) << render.err;
  EXPECT_FALSE(fs::exists(dir_ / "out/r"));
  const test::CliResult view = test::run_cli("view " + scene + " --light 1", "validation",
                                             test::kHangBound + " env -u DISPLAY -u WAYLAND_DISPLAY");
  EXPECT_EQ(view.exit_code, 2) << view.err;
  EXPECT_NE(view.err.find("--light 1 is out of range (the scene has 1 light(s))"), std::string::npos) << view.err;
}

}  // namespace
}  // namespace nearcap
