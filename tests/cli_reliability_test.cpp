// The program against what a careful outsider tried: outputs onto special
// files, partial outputs, derived-camera crashes, unbounded reads, usage
// conventions.  Each test is one reproduction; every failure must be one line
// starting "nearcap: error", exit code 2, and leave no output behind.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "cli_support.hpp"
#include "nearcap/raytrace/shadow_ray_tracer.hpp"

namespace nearcap {
namespace {

namespace fs = std::filesystem;

// Scene "B" of the reliability report: a box over the ground, 64 x 48.
nlohmann::json scene_b() {
  return nlohmann::json::parse(R"({"camera":{"eye":[0,2.5,5],"target":[0,0.7,0],"up":[0,1,0],"fovy_deg":50,
    "near":0.1,"far":100,"width":64,"height":48},"lights":[{"position":[2,5,1.5]}],
    "objects":[{"mesh":"box.off","translate":[0,1,0]},{"mesh":"ground.off","occluder":false}]})");
}

class Reliability : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("nearcap_reliability_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    for (const char* mesh : {"box.off", "ground.off"})
      fs::copy_file(fs::path(NEARCAP_SOURCE_DIR) / "data/meshes" / mesh, dir_ / mesh);
    write_scene("B.json", scene_b());
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  void write_scene(const std::string& name, const nlohmann::json& j) const { std::ofstream(dir_ / name) << j.dump(); }
  void write_text(const std::string& name, const std::string& text) const { std::ofstream(dir_ / name) << text; }
  test::CliResult run(const std::string& args, const std::string& prefix = test::kHangBound) const {
    return test::run_cli(args, "reliability", prefix);
  }
  // One line, "nearcap: error", exit 2, containing `fragment`, nothing on stdout.
  static void expect_one_line_error(const test::CliResult& r, const std::string& fragment, const std::string& what) {
    EXPECT_EQ(r.exit_code, 2) << what << "\n" << r.err;
    EXPECT_EQ(r.err.rfind("nearcap: error", 0), 0u) << what << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << what << "\n" << r.err;
    EXPECT_NE(r.err.find(fragment), std::string::npos) << what << ": expected '" << fragment << "' in\n" << r.err;
    EXPECT_TRUE(r.out.empty()) << what << "\n" << r.out;
  }
  std::set<std::string> entries(const std::string& d) const {
    std::set<std::string> names;
    for (const auto& e : fs::directory_iterator(dir_ / d)) names.insert(e.path().filename().string());
    return names;
  }
  fs::path dir_;
};

// ---- 1. special files -------------------------------------------------------

TEST_F(Reliability, AFifoDestinationIsWrittenThroughNotReplaced) {
  ASSERT_EQ(::mkfifo(path("f").c_str(), 0600), 0);
  std::string received;
  std::thread reader([&] { received = test::slurp(path("f")); });
  const test::CliResult r = run("cap " + path("B.json") + " --light 0 --out " + path("f"));
  reader.join();
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(nlohmann::json::accept(received)) << received;
  struct stat st {};
  ASSERT_EQ(::lstat(path("f").c_str(), &st), 0);
  EXPECT_TRUE(S_ISFIFO(st.st_mode));
}

TEST_F(Reliability, ASymlinkDestinationKeepsTheLinkAndWritesItsTarget) {
  write_text("target.json", "old");
  fs::create_symlink("target.json", path("link.json"));
  const test::CliResult r = run("cap " + path("B.json") + " --light 0 --out " + path("link.json"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::is_symlink(path("link.json")));
  EXPECT_TRUE(nlohmann::json::accept(test::slurp(path("target.json"))));
}

TEST_F(Reliability, ProcSelfFdOneReachesStandardOutput) {
  const test::CliResult r = run("cap " + path("B.json") + " --light 0 --out /proc/self/fd/1");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // The JSON went through the descriptor into the captured stdout, followed by the summary lines.
  EXPECT_NE(r.out.find("\"near_rectangle\""), std::string::npos) << r.out;
}

TEST_F(Reliability, DevNullIsACharacterDevice) {
  // Run by the suite, and again by scripts/test.sh after the whole suite.
  struct stat st {};
  ASSERT_EQ(::stat("/dev/null", &st), 0);
  EXPECT_TRUE(S_ISCHR(st.st_mode)) << "/dev/null is not a character device: restore it with "
                                      "'rm /dev/null && mknod -m 666 /dev/null c 1 3'";
}

// ---- 2. partial outputs -----------------------------------------------------

TEST_F(Reliability, ReferenceLeavesNothingWhenAnyOutputIsBlocked) {
  for (const char* blocked : {"cap.pgm", "stencil.pgm", "shadow.png", "reference.json"}) {
    const std::string d = std::string("ref_") + blocked;
    fs::create_directories(dir_ / d / blocked / "sub");
    const test::CliResult r = run("reference " + path("B.json") + " --light 0 --out " + path(d));
    expect_one_line_error(r, blocked, blocked);
    EXPECT_EQ(entries(d), (std::set<std::string>{blocked})) << blocked;
  }
}

TEST_F(Reliability, CracksLeavesNoImageWhenItsJsonIsBlocked) {
  fs::create_directories(dir_ / "c" / "cracks.json");
  const test::CliResult r = run("cracks " + path("B.json") + " --light 0 --out " + path("c"));
  expect_one_line_error(r, "cracks.json", "cracks");
  EXPECT_EQ(entries("c"), (std::set<std::string>{"cracks.json"}));
}

TEST_F(Reliability, CapLeavesNoJsonWhenItsSvgIsBlocked) {
  fs::create_directories(dir_ / "s" / "x.svg");
  const test::CliResult r =
      run("cap " + path("B.json") + " --light 0 --out " + path("s/out.json") + " --svg " + path("s/x.svg"));
  expect_one_line_error(r, "x.svg", "cap");
  EXPECT_EQ(entries("s"), (std::set<std::string>{"x.svg"}));
}

TEST_F(Reliability, TwoOutputsWithOnePathAreRejectedUpFront) {
  const test::CliResult r =
      run("cap " + path("B.json") + " --light 0 --out " + path("same.json") + " --svg " + path("same.json"));
  expect_one_line_error(r, "same file", "cap");
  EXPECT_FALSE(fs::exists(path("same.json")));
}

TEST_F(Reliability, AFailedRunLeavesNoNewOutputDirectory) {
  fs::create_directories(dir_ / "blocked.json");
  const test::CliResult r =
      run("cap " + path("B.json") + " --light 0 --out " + path("blocked.json") + " --svg " + path("new/dir/x.svg"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_FALSE(fs::exists(path("new")));
}

TEST_F(Reliability, NoCommandReplacesTheFilesItReads) {
  const std::string scene = test::slurp(path("B.json"));
  expect_one_line_error(run("cap " + path("B.json") + " --light 0 --out " + path("B.json")), "would replace the scene",
                        "cap --out");
  expect_one_line_error(run("cap " + path("B.json") + " --light 0 --svg " + path("B.json")), "would replace the scene",
                        "cap --svg");
  write_scene("reference.json", scene_b());
  expect_one_line_error(run("reference " + path("reference.json") + " --light 0 --out " + dir_.string()),
                        "would replace the scene", "reference");
  write_scene("cracks.json", scene_b());
  expect_one_line_error(run("cracks " + path("cracks.json") + " --light 0 --method zfail --out " + dir_.string()),
                        "would replace the scene", "cracks");
  write_text(
      "path.json",
      R"({"scene":"B.json","frames":2,"keyframes":[{"eye":[0,2.5,5],"target":[0,0.7,0]},{"eye":[0,2.5,4],"target":[0,0.7,0]}]})");
  const std::string path_text = test::slurp(path("path.json"));
  expect_one_line_error(run("frame " + path("path.json") + " --frame 0 --out " + path("path.json")),
                        "would replace the camera path file", "frame onto its path");
  expect_one_line_error(run("frame " + path("path.json") + " --frame 0 --out " + path("B.json")),
                        "would replace the scene file", "frame onto its scene");
  const std::string box = test::slurp(path("box.off"));
  expect_one_line_error(run("cap " + path("B.json") + " --light 0 --out " + path("box.off")),
                        "would replace the mesh file", "cap onto a mesh");
  expect_one_line_error(run("frame " + path("path.json") + " --frame 0 --out " + path("box.off")),
                        "would replace the mesh file", "frame onto a mesh");
  expect_one_line_error(run("calibrate --path " + path("path.json") + " --out " + path("path.json")),
                        "would replace the camera path file", "calibrate onto its path");
  expect_one_line_error(run("calibrate --path " + path("path.json") + " --out " + path("B.json")),
                        "would replace the scene file", "calibrate onto its path's scene");
  expect_one_line_error(run("calibrate --path " + path("path.json") + " --out " + path("box.off")),
                        "would replace the mesh file", "calibrate onto its path's mesh");
  expect_one_line_error(run("evaluate --path " + path("path.json") + " --fit-unpriced " + path("box.off") + " --out " +
                            path("evaluated")),
                        "would replace the mesh file", "evaluate's fit onto its path's mesh");
  write_scene("render.json", scene_b());
  expect_one_line_error(run("render " + path("render.json") + " --method zpass --out " + dir_.string()),
                        "would replace the scene file", "render's lit frames onto the scene");
  expect_one_line_error(run("view " + path("B.json") + " --screenshot " + path("box.off") + " --keys w"),
                        "would replace the mesh file", "view's screenshot onto a mesh");
  // A policy file named as an output: render.json, evaluate's table, calibrate's CSV.
  fs::create_directories(dir_ / "policy");
  const std::string policy = test::slurp(fs::path(NEARCAP_SOURCE_DIR) / "data/policy.json");
  for (const char* name : {"render.json", "table.md", "P.json"}) write_text("policy/" + std::string(name), policy);
  expect_one_line_error(run("render " + path("B.json") + " --method policy --policy " + path("policy/render.json") +
                            " --out " + path("policy")),
                        "would replace the policy file", "render onto its policy");
  expect_one_line_error(run("evaluate --samples 1 --policy " + path("policy/table.md") + " --out " + path("policy")),
                        "would replace the policy file", "evaluate onto its policy");
  expect_one_line_error(run("calibrate --samples 1 --policy " + path("policy/P.json") + " --write-policy " +
                            path("W.json") + " --out " + path("policy/P.json")),
                        "would replace the policy file", "calibrate's observations onto its policy");
  EXPECT_EQ(test::slurp(path("box.off")), box);
  EXPECT_EQ(test::slurp(path("B.json")), scene);
  EXPECT_EQ(test::slurp(path("reference.json")), scene);
  EXPECT_EQ(test::slurp(path("cracks.json")), scene);
  EXPECT_EQ(test::slurp(path("render.json")), scene);
  EXPECT_EQ(test::slurp(path("path.json")), path_text);
  for (const char* name : {"render.json", "table.md", "P.json"})
    EXPECT_EQ(test::slurp(path("policy/" + std::string(name))), policy) << name;
  EXPECT_FALSE(fs::exists(path("W.json")));
}

// The sampler's meshes ($NEARCAP_DATA_DIR/meshes) are what every sampling
// command reads: no output replaces one.
TEST_F(Reliability, NoSamplingCommandReplacesTheSamplersMeshes) {
  fs::create_directories(dir_ / "data/meshes");
  for (const char* mesh : {"box.off", "torus.off", "eight.off", "knot1.off"})
    fs::copy_file(fs::path(NEARCAP_SOURCE_DIR) / "data/meshes" / mesh, dir_ / "data/meshes" / mesh);
  const std::string box = test::slurp(path("data/meshes/box.off"));
  const std::string knot = test::slurp(path("data/meshes/knot1.off"));
  const std::string env = "NEARCAP_DATA_DIR='" + path("data") + "' " + test::kHangBound;
  auto sampling = [&](const std::string& args) { return test::run_cli(args, "reliability", env); };
  expect_one_line_error(sampling("sample --index 0 --out " + path("data/meshes/box.off")),
                        "would replace the sampler's mesh file", "sample");
  expect_one_line_error(sampling("fit-l-near --samples 2 --kinds grazing --out " + path("data/meshes/knot1.off")),
                        "would replace the sampler's mesh file", "fit-l-near");
  expect_one_line_error(sampling("calibrate --samples 1 --width 16 --height 12 --out " + path("data/meshes/box.off")),
                        "would replace the sampler's mesh file", "calibrate");
  expect_one_line_error(sampling("evaluate --samples 1 --repeats 1 --fit-unpriced " + path("data/meshes/knot1.off") +
                                 " --out " + path("evaluated")),
                        "would replace the sampler's mesh file", "evaluate's fit");
  EXPECT_EQ(test::slurp(path("data/meshes/box.off")), box);
  EXPECT_EQ(test::slurp(path("data/meshes/knot1.off")), knot);
}

// A new sweep writes its sidecar, OUT.meta.json: a file of that name that is
// not a sweep's sidecar (here the policy the sweep reads) is never replaced;
// an earlier sweep's sidecar left behind by a removed CSV is.
TEST_F(Reliability, ANewSweepNeverReplacesAFileNamedAsItsSidecarThatIsNotOne) {
  const std::string policy = test::slurp(fs::path(NEARCAP_SOURCE_DIR) / "data/policy.json");
  write_text("r.csv.meta.json", policy);
  expect_one_line_error(run("sweep --samples 1 --width 8 --height 6 --methods zpass --policies policy --policy " +
                            path("r.csv.meta.json") + " --out " + path("r.csv")),
                        "is taken by a file that is not a sweep's sidecar", "the sweep's own policy");
  EXPECT_EQ(test::slurp(path("r.csv.meta.json")), policy);
  EXPECT_FALSE(fs::exists(path("r.csv")));
  // A link from the sidecar's name to the CSV: the sidecar would replace the
  // rows.
  fs::create_symlink("l.csv", dir_ / "l.csv.meta.json");
  expect_one_line_error(run("sweep --samples 1 --width 8 --height 6 --methods zpass --out " + path("l.csv")),
                        "is taken by a file that is not a sweep's sidecar", "a sidecar linked to its CSV");
  EXPECT_FALSE(fs::exists(path("l.csv")));
  const std::string sweep = "sweep --samples 1 --width 8 --height 6 --methods zpass --out " + path("s.csv");
  ASSERT_EQ(run(sweep).exit_code, 0);
  fs::remove(path("s.csv"));
  const test::CliResult again = run(sweep);
  EXPECT_EQ(again.exit_code, 0) << again.err;
}

// An output where no file can be made is refused before the work that would
// fill it (calibrate measures for minutes; the write would fail at the end).
TEST_F(Reliability, AnUnwritableOutputIsRefusedBeforeTheWork) {
  expect_one_line_error(run("calibrate --samples 1 --out /proc/nearcap-calibration.csv"), "cannot write in /proc",
                        "calibrate into /proc");
  expect_one_line_error(run("tune " + path("none.csv") + " --out /proc/nearcap-policy.json"), "cannot write in /proc",
                        "tune into /proc");
  // A folder still to be made: its deepest existing ancestor is asked.
  expect_one_line_error(run("tune " + path("none.csv") + " --out /proc/nearcap-folder/policy.json"),
                        "cannot write in /proc", "tune into a new folder in /proc");
}

// NEARCAP_DATA_DIR names where the sampler's meshes are: a folder without
// them is an error, not a sweep of rejected rows.
TEST_F(Reliability, ADataDirectoryWithoutTheMeshesIsAnError) {
  const test::CliResult r = test::run_cli("sweep --samples 2 --width 8 --height 6 --out " + path("s.csv"),
                                          "reliability", "NEARCAP_DATA_DIR='" + path("nowhere") + "'");
  expect_one_line_error(r, "NEARCAP_DATA_DIR=", "a data directory without meshes");
  EXPECT_FALSE(fs::exists(path("s.csv")));
  // A sweep of a camera path alone samples nothing: it runs.
  const test::CliResult paths = test::run_cli(
      "sweep --path data/paths/near_plane_sweep.json --width 8 --height 6 --methods zpass --out " + path("p.csv"),
      "reliability", "NEARCAP_DATA_DIR='" + path("nowhere") + "'");
  EXPECT_EQ(paths.exit_code, 0) << paths.err;
}

// A data folder that lacks one of the sampler's meshes, or holds a broken
// one, is one error naming the file, before anything is sampled (every
// configuration naming it would be rejected, or a fit made on the others).
TEST_F(Reliability, ADataDirectoryWithAMissingOrBrokenMeshIsAnError) {
  fs::create_directories(dir_ / "data/meshes");
  for (const char* mesh : {"box.off", "torus.off", "eight.off"})
    fs::copy_file(fs::path(NEARCAP_SOURCE_DIR) / "data/meshes" / mesh, dir_ / "data/meshes" / mesh);
  const std::string env = "NEARCAP_DATA_DIR='" + path("data") + "' " + test::kHangBound;
  auto sampling = [&](const std::string& args) { return test::run_cli(args, "reliability", env); };
  expect_one_line_error(sampling("fit-l-near --samples 20 --width 32 --height 24"), "knot1.off", "fit-l-near");
  expect_one_line_error(sampling("sweep --samples 2 --width 8 --height 6 --out " + path("s.csv")), "knot1.off",
                        "sweep");
  EXPECT_FALSE(fs::exists(path("s.csv")));
  fs::copy_file(fs::path(NEARCAP_SOURCE_DIR) / "data/meshes/knot1.off", dir_ / "data/meshes/knot1.off");
  write_text("data/meshes/box.off", "garbage\n");
  const test::CliResult broken = sampling("sample --index 0");
  expect_one_line_error(broken, "a mesh of the sampler does not load: " + path("data/meshes/box.off"),
                        "a broken box.off");
  EXPECT_EQ(broken.err.rfind("nearcap: error (parse): NEARCAP_DATA_DIR=", 0), 0u) << broken.err;
}

// evaluate's and render --bench's plots are drawn by Python after the
// measuring: a Python that cannot draw them is an error before it.
TEST_F(Reliability, APlotsPythonIsCheckedBeforeTheMeasuring) {
  const std::string env = "NEARCAP_PYTHON=/bin/false " + std::string(test::kHangBound);
  const test::CliResult evaluate = test::run_cli(
      "evaluate --path data/paths/near_plane_sweep.json --repeats 1 --width 8 --height 6 --out " + path("evaluated"),
      "reliability", env);
  expect_one_line_error(evaluate, "policy_oracle.py: the policy-against-oracle plot's script exited with status 1",
                        "evaluate");
  EXPECT_FALSE(fs::exists(path("evaluated")));
  const test::CliResult render =
      test::run_cli("render --path data/paths/near_plane_sweep.json --method zpass --bench --out " + path("rendered"),
                    "reliability", env);
  expect_one_line_error(render, "render_bench.py: the bench plot's script exited with status 1", "render");
  EXPECT_FALSE(fs::exists(path("rendered")));
  // No temporary directory for the script's log: its messages are kept in
  // memory, and the line quotes the last one.
  const test::CliResult no_tmp = test::run_cli(
      "evaluate --path data/paths/near_plane_sweep.json --repeats 1 --width 8 --height 6 --out " + path("evaluated"),
      "reliability", "TMPDIR=/proc NEARCAP_PYTHON=/bin/ls " + std::string(test::kHangBound));
  expect_one_line_error(no_tmp, "exited with status 2 (NEARCAP_PYTHON=/bin/ls) without an error line; its last line: ",
                        "no temporary directory");
}

// fit-l-near reads the light frustum's options alone: the others, and the
// scale it fits, are unknown to it; the clipped-sides cap has no l_near.
// Its JSON names every option that made the fit.
TEST_F(Reliability, FitLNearTakesOnlyTheOptionsItReads) {
  for (const char* option : {"--depth float32", "--l-near-scale 0.5", "--fma", "--guard-band 100"}) {
    const test::CliResult r = run("fit-l-near --samples 4 " + std::string(option));
    EXPECT_EQ(r.exit_code, 2) << option << "\n" << r.err;
    EXPECT_EQ(r.err.rfind("nearcap: error (usage): ", 0), 0u) << option << "\n" << r.err;
  }
  expect_one_line_error(run("fit-l-near --samples 4 --light-projection clipped-sides"), "no l_near to fit",
                        "clipped-sides");
  const test::CliResult fit =
      run("fit-l-near --samples 6 --width 40 --height 20 --l-near near-clamp --out " + path("fit.json"));
  ASSERT_EQ(fit.exit_code, 0) << fit.err;
  const std::string command = nlohmann::json::parse(test::slurp(path("fit.json")))["command"];
  for (const char* part : {"--samples 6", "--width 40", "--height 20", "--l-near near-clamp", "--light-projection"})
    EXPECT_NE(command.find(part), std::string::npos) << part << " not in " << command;
}

// A file where an output directory goes is refused before any work (the
// writes would fail only at the end, after the frames are drawn).
TEST_F(Reliability, AFileNamedAsTheOutputDirectoryIsRefusedUpFront) {
  write_text("afile", "kept");
  const std::string out = " --out " + path("afile");
  for (const std::string& args :
       {"cracks " + path("B.json") + " --light 0" + out, "render " + path("B.json") + " --light 0 --compare" + out,
        "render " + path("B.json") + out, "evaluate --samples 1" + out, "view " + path("B.json") + out,
        "reference " + path("B.json") + " --light 0" + out}) {
    const test::CliResult r = run(args);
    expect_one_line_error(r, "--out '" + path("afile") + "' is there and is not a directory", args);
  }
  expect_one_line_error(run("cracks " + path("B.json") + " --light 0 --out " + path("afile/sub")),
                        "a folder on its way is a file", "a file on the way");
  EXPECT_EQ(test::slurp(path("afile")), "kept");
}

TEST_F(Reliability, AFullStandardOutputIsAnError) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  // Run directly: run_cli redirects stdout to a file of its own.  A
  // command's output, the version, and help in each of its spellings.
  for (const std::string& args : {"classify '" + path("B.json") + "'", std::string("--version"), std::string("--help"),
                                  std::string("cap --help"), std::string("help cap")}) {
    SCOPED_TRACE(args);
    const std::string command =
        "'" + std::string(NEARCAP_CLI) + "' " + args + " > /dev/full 2> '" + path("err.txt") + "'";
    const int status = std::system(command.c_str());
    EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 2);
    const std::string err = test::slurp(path("err.txt"));
    EXPECT_EQ(err.rfind("nearcap: error (io): standard output", 0), 0u) << err;
    EXPECT_NE(err.find(std::strerror(ENOSPC)), std::string::npos) << err;  // the reason, /dev/full's
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  }
}

TEST_F(Reliability, ACameraPathNamedWithoutAFolderIsReadFromTheWorkingFolder) {
  write_text(
      "path.json",
      R"({"scene":"B.json","frames":2,"keyframes":[{"eye":[0,2.5,5],"target":[0,0.7,0]},{"eye":[0,2.5,4],"target":[0,0.7,0]}]})");
  const test::CliResult r = test::run_cli("frame path.json --frame 1", "reliability", "cd '" + dir_.string() + "' &&");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find((dir_ / "box.off").lexically_normal().string()), std::string::npos) << r.out;
  const test::CliResult s = test::run_cli("classify B.json", "reliability", "cd '" + dir_.string() + "' &&");
  EXPECT_EQ(s.exit_code, 0) << s.err;
}

TEST_F(Reliability, FrameRefusesAFrameNoOtherCommandWouldRead) {
  // The up vectors interpolate to zero halfway.
  write_text("flip.json",
             R"({"scene":"B.json","frames":3,"keyframes":[{"eye":[0,2.5,5],"target":[0,0.7,0],"up":[0,1,0]},
    {"eye":[0,2.5,5],"target":[0,0.7,0],"up":[0,-1,0]}]})");
  EXPECT_EQ(run("frame " + path("flip.json") + " --frame 0").exit_code, 0);
  expect_one_line_error(run("frame " + path("flip.json") + " --frame 1 --out " + path("f1.json")),
                        "flip.json frame 1: camera.up", "frame 1");
  EXPECT_FALSE(fs::exists(path("f1.json")));
}

TEST_F(Reliability, MessagesShowTheBytesTheyQuoteAsText) {
  // A NUL in a mesh name does not cut the message short.
  nlohmann::json scene = scene_b();
  scene["objects"][0]["mesh"] = std::string("box.off\0.json", 13);
  write_scene("nul.json", scene);
  expect_one_line_error(run("classify " + path("nul.json")), "box.off\\0.json", "a NUL in a mesh name");
  // A binary file read as OFF: the word quoted is printable.
  std::string garbage = "\xcf\xbc\xb5\x97)'K+\x85\xae\xed\xa4\x15\xa6\xd6OUo\n3 1 0\n";
  write_text("garbage.off", garbage);
  scene = scene_b();
  scene["objects"][0]["mesh"] = "garbage.off";
  write_scene("garbage.json", scene);
  const test::CliResult g = run("classify " + path("garbage.json"));
  expect_one_line_error(g, "does not start with the keyword OFF", "a binary OFF");
  for (char c : g.err) EXPECT_TRUE(c == '\n' || (c >= 0x20 && c < 0x7f)) << g.err;
}

// calibrate takes a bundled path by its name; the other commands need its
// file, and name it.
TEST_F(Reliability, ABundledPathsNameWhereAFileIsNeededNamesTheFile) {
  const std::string file = std::string(NEARCAP_SOURCE_DIR) + "/data/paths/near_plane_sweep.json";
  for (const std::string& command :
       {"sweep --path near_plane_sweep --out " + path("n.csv"), std::string("frame near_plane_sweep.json --frame 0"),
        "render --path near_plane_sweep --out " + path("n"), "evaluate --path near_plane_sweep --out " + path("e")})
    expect_one_line_error(
        run(command),
        ": cannot open the camera path file (no such file; the bundled path of that name is " + file + ")", command);
  EXPECT_FALSE(fs::exists(path("n.csv")));
  expect_one_line_error(run("sweep --path no_such_path --out " + path("n.csv")),
                        "no_such_path: cannot open the camera path file (no such file)",
                        "no bundled path of that name");
}

TEST_F(Reliability, MethodListsAndOptionsAreNamedWhenWrong) {
  expect_one_line_error(run("cracks " + path("B.json") + " --light 0 --method zpass,zpass"),
                        "--method names zpass twice", "a method twice");
  expect_one_line_error(run("cracks " + path("B.json") + " --light 0 --method foo"), "raytrace, policy (or all)",
                        "an unknown method");
  expect_one_line_error(run("cracks " + path("B.json") + " --light 0 --method all,zpass"), "--method all stands alone",
                        "all with other names");
  expect_one_line_error(run("sweep --samples 1 --methods zfail,all --out " + path("k.csv")),
                        "--methods all stands alone", "all with other names in a sweep");
  expect_one_line_error(run("sweep --samples 1 --policies doom3,none --out " + path("k.csv")),
                        "--policies none stands alone", "none with other names");
  expect_one_line_error(run("sample --kinds all,grazing --index 0"), "--kinds all stands alone",
                        "all with other kinds");
  expect_one_line_error(run("sweep --samples 1 --kinds grazing,grazing --out " + path("k.csv")),
                        "grazing is named twice", "a kind twice");
  expect_one_line_error(run("sweep --samples 1 --kinds grazing, --out " + path("k.csv")), "an empty kind name",
                        "a trailing comma in --kinds");
  // An unknown name in a list: the option, the names it takes, its help.
  expect_one_line_error(run("sample --kinds grazing,nope --index 0"),
                        "--kinds: 'nope' is not a hard-case kind (one of light-near-plane, ", "an unknown kind");
  expect_one_line_error(run("sample --kinds nope --index 0"), ", or all) (see nearcap sample --help)",
                        "an unknown kind's help");
  expect_one_line_error(run("tune " + path("none.csv") + " --out " + path("p.json") + " --features log_skew,log_magic"),
                        "--features: 'log_magic' is not a policy feature (one of log_light_near_distance, "
                        "log_l_far_over_width, log_delta_over_width, log_skew, log_cond_light_transform, "
                        "log_cap_window_error_px, log_coordinate_over_size, l_near_over_l_far; or all, or none) "
                        "(see nearcap tune --help)",
                        "an unknown feature, before any row is read");
  expect_one_line_error(
      run("tune " + path("none.csv") + " --out " + path("p.json") + " --features log_skew,log_skew"),
      "--features 'log_skew,log_skew': 'log_skew' is named twice (each once) (see nearcap tune --help)",
      "a feature twice, before any row is read");
  expect_one_line_error(run("tune " + path("none.csv") + " --out " + path("p.json") + " --features log_skew,"),
                        "--features 'log_skew,': an empty feature name (see nearcap tune --help)",
                        "a trailing comma in --features");
  // The real-GL commands draw no ray tracer, and do not offer it.
  for (const std::string command : {"render", "view"}) {
    const test::CliResult r = run(command + " " + path("B.json") + " --light 0 --method foo --out " + path("r"));
    expect_one_line_error(r, "--method 'foo' is not one of zpass, ", command + ": an unknown method");
    EXPECT_EQ(r.err.find("raytrace"), std::string::npos) << r.err;
  }
  expect_one_line_error(run("cracks " + path("B.json") + " --light 99999999999999999999"),
                        "--light: '99999999999999999999' is far above any scene's number of lights",
                        "a light index too large to read");
  // Leading zeros are no part of the value: light 1 of a one-light scene.
  expect_one_line_error(run("cracks " + path("B.json") + " --light 00000000001"),
                        "--light 1 is out of range (the scene has 1 light(s))", "a light index with leading zeros");
  expect_one_line_error(run("cracks " + path("B.json") + " --light 010"), "--light 10 is out of range",
                        "a leading zero: decimal, not octal");
  expect_one_line_error(run("cracks " + path("B.json") + " --light 08"), "--light 8 is out of range",
                        "a leading zero before a digit octal lacks");
  EXPECT_FALSE(fs::exists(path("k.csv")));
  expect_one_line_error(run("--bogus classify " + path("B.json")), "unknown option '--bogus'", "an option first");
  expect_one_line_error(run("cap " + path("B.json") + " --light 0 --out ''"), "--out: the file name is empty",
                        "an empty --out");
  expect_one_line_error(run("cap " + path("B.json") + " --light 0 --light 1"),
                        "--light is given 2 times (give it once)", "an option twice");
  expect_one_line_error(run("cracks " + path("B.json") + " --light 0 --table --table --table"),
                        "--table is given 3 times (give it once)", "a flag three times");
  expect_one_line_error(run("sweep --samples 1 --allow-bunny --allow-bunny --out " + path("k.csv")),
                        "--allow-bunny is given 2 times (give it once)", "a flag twice");
  expect_one_line_error(run("classify " + path("B.json") + " first second third"),
                        "unexpected arguments: first second third", "extras in the order given");
  // A misspelt option is named, with the subcommand's nearest option, also
  // where it leaves a required option missing; the help named is the
  // subcommand's.
  expect_one_line_error(run("cracks " + path("B.json") + " --ligth 0"),
                        "unknown option '--ligth' (did you mean --light?) (see nearcap cracks --help)",
                        "a misspelt required option");
  expect_one_line_error(run("cap " + path("B.json") + " --light 0 --svgg=x.svg"),
                        "unknown option '--svgg' (did you mean --svg?) (see nearcap cap --help)",
                        "a misspelt option with its value after =");
  expect_one_line_error(run("cracks " + path("B.json") + " --light 0 --frobnicate"),
                        "unknown option '--frobnicate' (see nearcap cracks --help)", "an option nothing is near");
  expect_one_line_error(run("cracks " + path("B.json") + " --light -1"), "--light: '-1' is not a light index",
                        "a negative value is a value, not an option");
  expect_one_line_error(run("cracks " + path("B.json") + " --light 0 -1"), "unexpected argument: -1",
                        "a negative number left over is an argument, not an option");
  expect_one_line_error(run("cracks " + path("B.json") + " --light 0 -q"), "unknown option '-q' (see nearcap",
                        "a short option nothing is near");
  expect_one_line_error(run("cracks " + path("B.json") + " --light 0 --metho zpass"),
                        "unknown option '--metho' (did you mean --method?)", "one letter short");
  expect_one_line_error(run("cracks " + path("B.json") + " --light 0 --zfaxs-far finite"),
                        "unknown option '--zfaxs-far' (see nearcap",
                        "two edits from --zfail-far and from --zpass-far: no name suggested");
  expect_one_line_error(run("cap --light x -- " + path("B.json")), "--light: 'x'",
                        "after --, the value's own error, not '--' as an option");
  // A policy's whole number written as a float.
  nlohmann::json policy = nlohmann::json::parse(test::slurp(std::string(NEARCAP_SOURCE_DIR) + "/data/policy.json"));
  policy["unpriced_frames"][0]["max_occluder_triangles"] = 1e30;
  write_scene("p.json", policy);
  expect_one_line_error(run("cracks " + path("B.json") + " --light 0 --method policy --policy " + path("p.json")),
                        "a whole number written as a float", "1e30 triangles");
  // tune checks its --out before fitting: nothing printed.
  fs::create_directories(dir_ / "outdir");
  write_text("rows.csv", "configuration\n");
  expect_one_line_error(run("tune " + path("rows.csv") + " --out " + path("outdir")), "outdir", "tune --out DIR");
}

// ---- 3. derived cameras -----------------------------------------------------

TEST_F(Reliability, AnEyeBeyondTheFloatRangeIsARangeError) {
  for (const double z : {1e160, 1e200, 1e300}) {
    nlohmann::json j = scene_b();
    j["camera"]["eye"] = {0, 2.5, z};
    write_scene("far_eye.json", j);
    for (const std::string cmd : {"classify", "cap", "reference"}) {
      const std::string extra = cmd == "classify" ? "" : " --light 0 --out " + path("o_" + cmd);
      const test::CliResult r = run(cmd + " " + path("far_eye.json") + extra);
      expect_one_line_error(r, "camera.eye[2]", cmd);
      EXPECT_FALSE(fs::exists(path("o_" + cmd)));
    }
  }
}

TEST_F(Reliability, TinyViewDirectionsAndUpVectorsGiveTheRightBasis) {
  // Both vectors' squared lengths underflow, so gluLookAt's plain
  // normalisation would divide by zero (scene/camera.cpp rescales them
  // first); both are legitimate cameras: looking down +z, up +y.
  nlohmann::json tiny_target = scene_b();
  tiny_target["camera"]["eye"] = {0, 0.7, 0};
  tiny_target["camera"]["target"] = {0, 0.7, 1e-300};
  nlohmann::json tiny_up = scene_b();
  tiny_up["camera"]["up"] = {0, 1e-300, 0};
  nlohmann::json plain_up = scene_b();
  write_scene("tiny_target.json", tiny_target);
  write_scene("tiny_up.json", tiny_up);
  write_scene("plain_up.json", plain_up);
  for (const char* name : {"tiny_target.json", "tiny_up.json"}) {
    for (const std::string cmd : {"classify --json", "cap", "reference"}) {
      const std::string extra = cmd == "classify --json" ? "" : " --light 0 --out " + path("o_" + cmd + "_" + name);
      const test::CliResult r = run(cmd + " " + path(name) + extra);
      EXPECT_EQ(r.exit_code, 0) << name << " " << cmd << "\n" << r.err;
    }
  }
  // up = 1e-300 y is the same camera as up = y: identical classification.
  EXPECT_EQ(run("classify --json " + path("tiny_up.json")).out, run("classify --json " + path("plain_up.json")).out);
}

TEST_F(Reliability, AFloat32DegenerateViewIsRefusedByTheFloatPipelineOnly) {
  nlohmann::json j = scene_b();
  j["camera"] = nlohmann::json::parse(R"({"view":[[1e-50,0,0,0],[0,1e-50,0,0],[0,0,1e-50,-5],[0,0,0,1]],
    "frustum":{"left":-0.5,"right":0.5,"bottom":-0.375,"top":0.375,"near":0.5,"far":64},"width":64,"height":48})");
  write_scene("tiny_view.json", j);
  EXPECT_EQ(run("classify " + path("tiny_view.json")).exit_code, 0);
  for (const char* method : {"zfail", "preload", "zpass", "zpplus", "zpplus-corrected", "raytrace", "all"}) {
    if (std::string(method) == "raytrace" && !raytrace::raytrace_available()) continue;
    const test::CliResult r = run("cracks " + path("tiny_view.json") + " --light 0 --method " + method);
    expect_one_line_error(r, "float32", method);
  }
}

TEST_F(Reliability, ADenormalNearPlaneNamesNear) {
  nlohmann::json j = scene_b();
  j["camera"]["near"] = 5e-324;
  write_scene("denormal_near.json", j);
  const test::CliResult r = run("classify " + path("denormal_near.json"));
  expect_one_line_error(r, "camera.near", "near");
  EXPECT_EQ(r.err.find("left"), std::string::npos) << "left is not a key of the look-at form: " << r.err;
}

// ---- 4. bounded reads -------------------------------------------------------

TEST_F(Reliability, MeshesThatAreNotRegularFilesAreRefusedWithoutReading) {
  fs::create_symlink("/dev/zero", path("zero.off"));
  ASSERT_EQ(::mkfifo(path("fifo.off").c_str(), 0600), 0);
  fs::create_directories(dir_ / "dir.off");
  const std::pair<const char*, const char*> cases[] = {{"zero.off", "character device"},
                                                       {"fifo.off", "FIFO"},
                                                       {"dir.off", "directory"},
                                                       {"/dev/zero", "no extension"},
                                                       {"noext", "no extension"}};
  for (const auto& [mesh, fragment] : cases) {
    nlohmann::json j = scene_b();
    j["objects"][0]["mesh"] = mesh;
    write_scene("m.json", j);
    // A reader that read /dev/zero or waited on the FIFO would be killed by the timeout.
    const test::CliResult r = run("classify " + path("m.json"), test::kHangBound);
    expect_one_line_error(r, fragment, mesh);
  }
}

TEST_F(Reliability, AScenePathThatIsADirectoryIsNamedAsSuch) {
  fs::create_directories(dir_ / "scene_dir.json");
  expect_one_line_error(run("classify " + path("scene_dir.json")), "is a directory", "scene");
}

TEST_F(Reliability, FilesOverTheInputLimitAreAResourceError) {
  const test::CliResult r = run("classify " + path("B.json"), "NEARCAP_MAX_INPUT_MB=1");
  EXPECT_EQ(r.exit_code, 0) << "the small scene is under 1 MB: " << r.err;
  // A mesh of 1.5 MB: comments count too.
  std::ofstream big(dir_ / "big.off");
  big << test::slurp(dir_ / "box.off");
  for (int k = 0; k < 30000; ++k) big << "# padding padding padding padding padding\n";
  big.close();
  nlohmann::json j = scene_b();
  j["objects"][0]["mesh"] = "big.off";
  write_scene("big.json", j);
  expect_one_line_error(run("classify " + path("big.json"), "NEARCAP_MAX_INPUT_MB=1"), "NEARCAP_MAX_INPUT_MB",
                        "big mesh");
  EXPECT_EQ(run("classify " + path("big.json"), "NEARCAP_MAX_INPUT_MB=2").exit_code, 0);
  const test::CliResult lots = run("classify " + path("B.json"), "NEARCAP_MAX_INPUT_MB=lots");
  expect_one_line_error(lots, "NEARCAP_MAX_INPUT_MB", "bad variable");
  // A usage error, but not of the command's options: no help page to see.
  EXPECT_EQ(lots.err.find("(see nearcap"), std::string::npos) << lots.err;
  // A whole number too large is named as such, whatever its length.
  for (const char* large : {"1099511627777", "17592186044416", "99999999999999999999999999"})
    expect_one_line_error(run("classify " + path("B.json"), std::string("NEARCAP_MAX_INPUT_MB=") + large),
                          "is above 1099511627776 megabytes", large);
  EXPECT_EQ(run("classify " + path("B.json"), "NEARCAP_MAX_INPUT_MB=1099511627776").exit_code, 0);
}

TEST_F(Reliability, AFrameOverTheMemoryLimitIsRefusedWithTheEstimate) {
  nlohmann::json j = scene_b();
  j["camera"]["width"] = 16384;
  j["camera"]["height"] = 16384;
  write_scene("huge.json", j);
  for (const std::string cmd : {"reference", "cracks"}) {
    const test::CliResult r =
        run(cmd + " " + path("huge.json") + " --light 0 --max-memory 2 --out " + path("o_" + cmd));
    expect_one_line_error(r, "needs about", cmd);
    EXPECT_NE(r.err.find("16384x16384"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("--max-memory"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(path("o_" + cmd)));
  }
  // The commands that draw configurations at --width x --height.
  for (const std::string& cmd :
       {"calibrate --samples 1 --out " + path("c.csv"), "evaluate --samples 1 --out " + path("e")}) {
    const test::CliResult r = run(cmd + " --width 16384 --height 16384 --max-memory 2");
    expect_one_line_error(r, "needs about", cmd);
    EXPECT_NE(r.err.find("16384x16384"), std::string::npos) << r.err;
  }
  EXPECT_FALSE(fs::exists(path("c.csv")));
  EXPECT_FALSE(fs::exists(path("e")));
  // Small frames, but so many configurations that what each keeps to the
  // end of the run passes the limit: refused before the first is drawn.
  for (const std::string& cmd :
       {"calibrate --samples 100000 --out " + path("c.csv"), "evaluate --samples 100000 --out " + path("e")}) {
    const test::CliResult r = run(cmd + " --width 16 --height 16 --max-memory 1");
    expect_one_line_error(r, "for each of 100000 configurations", cmd);
  }
  EXPECT_FALSE(fs::exists(path("c.csv")));
  EXPECT_FALSE(fs::exists(path("e")));
}

TEST_F(Reliability, AFailedAllocationIsAResourceError) {
#if defined(NEARCAP_TESTS_UNDER_ASAN)
  GTEST_SKIP() << "AddressSanitizer reserves more address space than the limit this test sets";
#else
  // --max-memory lets the frame past the estimate; the address-space limit
  // then makes its first large allocation fail.
  nlohmann::json j = scene_b();
  j["camera"]["width"] = 16384;
  j["camera"]["height"] = 16384;
  write_scene("huge.json", j);
  const test::CliResult r =
      run("reference " + path("huge.json") + " --light 0 --max-memory 100 --out " + path("o"), "ulimit -v 600000;");
  expect_one_line_error(r, "out of memory", "bad_alloc");
  EXPECT_NE(r.err.find("error (resource)"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(path("o")));
#endif
}

// ---- 5. usage conventions ---------------------------------------------------

TEST_F(Reliability, EveryUsageErrorIsOneLineWithExitCodeTwo) {
  const std::string b = path("B.json");
  const std::pair<std::string, std::string> cases[] = {
      {"classify " + b + " --light abc", "--light"},  // classify has no --light: an extra argument
      {"cap " + b + " --light abc", "not a light index"},
      {"cap " + b + " --light 1e0", "not a light index"},
      {"cap " + b + " --light -1", "not a light index"},
      {"cap " + b + " --light ''", "not a light index"},
      {"cap " + b + " --light", "--light"},
      {"cap " + b + " --light 0 --light 0", "--light"},
      {"cap " + b, "--light"},
      {"reference " + b + " --light 0", "--out"},
      {"classify ''", "the scene file's name is empty"},
      {"bogus", "unknown subcommand 'bogus'"},
      {"optimize x", "unknown subcommand 'optimize'"},
      {"tune x", "--out is required"},
      {"classify " + b + " --bogus", "--bogus"},
      {"classify " + b + " extra", "extra"},
      {"cap " + b + " --light 3", "out of range"},
      // A --policy that no method chosen reads (a broken one would pass unread).
      {"cracks " + b + " --light 0 --method zfail --policy " + b,
       "--policy is read only with --method policy (or all)"},
      {"render " + b + " --method zpass --policy " + b + " --out " + path("r"),
       "--policy is read only with --method policy (or all)"},
      {"sweep --samples 1 --policies doom3 --policy " + b + " --out " + path("s.csv"),
       "--policy is read only with --policies policy (or all)"},
      // Another option that nothing chosen reads.
      {"cracks " + b + " --light 0 --method zpass --shadow-epsilon relative",
       "--shadow-epsilon is read only with --method raytrace (or all)"},
      {"sweep --path data/paths/zoom.json --seed 5 --out " + path("s.csv"),
       "--seed is read only with --samples: this command samples nothing"},
      {"sweep --path data/paths/zoom.json --allow-bunny --out " + path("s.csv"),
       "--allow-bunny is read only with --samples"},
      {"evaluate --path data/paths/zoom.json --kinds grazing --out " + path("e"),
       "--kinds is read only with --samples"},
      {"calibrate --samples 0 --path data/paths/zoom.json --seed 3 --out " + path("c.csv"),
       "--seed is read only with --samples"},
  };
  for (const auto& [args, fragment] : cases) expect_one_line_error(run(args), fragment, args);
}

TEST_F(Reliability, VersionAndHelpExitZero) {
  const test::CliResult v = run("--version");
  EXPECT_EQ(v.exit_code, 0);
  EXPECT_NE(v.out.find("nearcap 0."), std::string::npos) << v.out;
  // The version a sweep's sidecar records (which --resume compares) is the one printed.
  ASSERT_EQ(run("sweep --samples 1 --methods zfail --width 8 --height 6 --out " + path("v.csv")).exit_code, 0);
  const nlohmann::json meta = nlohmann::json::parse(test::slurp(path("v.csv.meta.json")));
  EXPECT_EQ(v.out, "nearcap " + meta.at("nearcap").get<std::string>() + "\n");
  const test::CliResult help = run("--help");
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_EQ(run("cracks --help").exit_code, 0);
  // `--help CMD` is `help CMD`: that command's help.
  const test::CliResult cracks_help = run("--help cracks");
  EXPECT_EQ(cracks_help.exit_code, 0);
  EXPECT_EQ(cracks_help.out, run("help cracks").out);
  EXPECT_NE(cracks_help.out, help.out);
}

TEST_F(Reliability, VersionAndHelpRefuseWhatTheyDoNotRead) {
  expect_one_line_error(run("--version extra"), "--version takes no arguments (found 'extra')", "version");
  expect_one_line_error(run("help cracks extra"), "help takes one subcommand's name (found 'extra' after 'cracks')",
                        "help");
  expect_one_line_error(run("--help cracks extra"), "found 'extra'", "--help");
}

TEST_F(Reliability, DuplicateKeysAreRejectedWithTheirPath) {
  write_text("dup.json", R"({"camera":{"eye":[0,2.5,5],"target":[0,0.7,0],"fovy_deg":50,"near":0.1,"far":100,
    "width":64,"height":48},"lights":[{"position":[2,5,1.5]}],
    "objects":[{"mesh":"box.off","translate":[0,1,0]},{"mesh":"ground.off","occluder":false,"occluder":true}]})");
  expect_one_line_error(run("classify " + path("dup.json")), "objects[1].occluder: duplicate key", "dup");
  write_text("dup_top.json", R"({"camera":{},"camera":{}})");
  expect_one_line_error(run("classify " + path("dup_top.json")), "camera: duplicate key", "dup top");
}

TEST_F(Reliability, IntegralWidthsAreAcceptedAndFractionsNamed) {
  nlohmann::json j = scene_b();
  j["camera"]["width"] = 64.0;
  write_scene("w.json", j);
  EXPECT_EQ(run("classify " + path("w.json")).exit_code, 0);
  j["camera"]["width"] = 64.5;
  write_scene("w.json", j);
  expect_one_line_error(run("classify " + path("w.json")), "must be an integer", "64.5");
}

}  // namespace
}  // namespace nearcap

namespace nearcap {
namespace {

// A hard configuration (the light 2^-24 before the near plane) whose float32
// light frustum maps a vertex to (0, 0, 0, 0): ZP+ refuses that frame with an
// error (range); with --method all the other methods still run and say so.
TEST_F(Reliability, AMethodThatRefusesTheFrameDoesNotStopTheOthers) {
  ASSERT_EQ(run("sample --seed 4073463411 --index 1620 --width 8 --height 8 --out " + path("k.json")).exit_code, 0);
  const test::CliResult all = run("cracks " + path("k.json") + " --light 0");
  ASSERT_EQ(all.exit_code, 0) << all.err;
  const nlohmann::json records = nlohmann::json::parse(all.out)["methods"];
  ASSERT_EQ(records.size(), 8u);  // the six methods, the switch policy and raytrace
  std::size_t refused = 0;
  for (const nlohmann::json& r : records) {
    if (r.contains("refused")) {
      ++refused;
      EXPECT_EQ(r["method"], "zpplus");
      EXPECT_NE(r["refused"].get<std::string>().find("degenerate"), std::string::npos) << r;
    } else {
      EXPECT_TRUE(r.contains("wrong")) << r;
    }
  }
  EXPECT_EQ(refused, 1u);
  // Asked for alone, the method's refusal is the command's one-line error.
  expect_one_line_error(run("cracks " + path("k.json") + " --light 0 --method zpplus"), "degenerate", "zpplus alone");
}

}  // namespace
}  // namespace nearcap
