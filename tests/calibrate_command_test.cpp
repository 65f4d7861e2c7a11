// `nearcap calibrate` on a tiny set (a few samples and a three-frame camera
// path at 32x24): every method's frames have the pass kinds it draws, with
// the emulation's own triangle and fragment counts, the CPU tasks are
// observed, and bad options are one-line errors.  Needs a headless GL;
// skipped without one, as the other real-GL tests are.
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

#include "cli_support.hpp"
#include "nearcap/analysis/calibration_file.hpp"
#include "nearcap/analysis/camera_path.hpp"
#include "nearcap/analysis/device_profile_fit.hpp"
#include "nearcap/analysis/switch_policy.hpp"
#include "nearcap/gl/shadow_methods.hpp"
#include "nearcap/io/scene_file.hpp"

namespace nearcap {
namespace {

namespace fs = std::filesystem;
using analysis::PassKind;

class CalibrateCommand : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("nearcap_calibrate_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    // near_plane_sweep in three frames: the last one's near plane cuts the
    // torus, so ZP+ draws a near-cap there.
    nlohmann::json p =
        nlohmann::json::parse(test::slurp(fs::path(NEARCAP_SOURCE_DIR) / "data/paths/near_plane_sweep.json"));
    p["scene"] = (fs::path(NEARCAP_SOURCE_DIR) / "data/scenes/room_side_light.json").string();
    p["frames"] = 3;
    path_ = dir_ / "sweep3.json";
    std::ofstream(path_) << p.dump(1);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_, path_;
};

// The observations of one frame name, by kind.
using ByKind = std::map<PassKind, analysis::PassObservation>;

TEST_F(CalibrateCommand, ObservesEveryPassKindEachMethodDrawsWithTheEmulationsCounts) {
  const fs::path csv = dir_ / "calibration.csv";
  const fs::path policy = dir_ / "calibrated-policy.json";
  const test::CliResult r =
      test::run_cli("calibrate --samples 3 --seed 5 --width 32 --height 24 --path '" + path_.string() + "' --out '" +
                        csv.string() + "' --write-policy '" + policy.string() + "'",
                    "calibrate");
  if (r.exit_code == 2 && r.err.find("error (gl)") != std::string::npos)
    GTEST_SKIP() << "no headless OpenGL here: " << r.err;
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("noise floor"), std::string::npos) << r.out;
  // Off a terminal the progress comes as lines, not carriage returns.
  EXPECT_EQ(r.err.find('\r'), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("calibrate: configuration 6/6, "), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("held out"), std::string::npos) << r.out;
  // The shipped policy with the fitted profile, naming this GL.
  const analysis::SwitchPolicy written = analysis::load_policy(policy.string());
  ASSERT_TRUE(written.device_profile);
  EXPECT_EQ(written.device_profile->origin, "calibrated");
  // The provenance says what the profile was measured on, beside the tuning's.
  const nlohmann::json provenance = nlohmann::json::parse(written.provenance_json);
  ASSERT_TRUE(provenance.contains("calibration")) << written.provenance_json;
  EXPECT_EQ(provenance["calibration"]["gl_renderer"], written.device_profile->gl_renderer);
  EXPECT_EQ(provenance["calibration"]["configurations"], 6);
  EXPECT_EQ(provenance["calibration"]["seed"], 5);
  EXPECT_EQ(r.out.rfind("calibrated on " + written.device_profile->gl_renderer + ":", 0), 0u) << r.out;
  EXPECT_GT(written.device_profile->passes[static_cast<std::size_t>(PassKind::Depth)].ms_per_mtriangle +
                written.device_profile->passes[static_cast<std::size_t>(PassKind::Depth)].ms_per_mfragment +
                written.device_profile->passes[static_cast<std::size_t>(PassKind::Depth)].intercept_ms,
            0.0);
  const analysis::CalibrationSet set = analysis::parse_calibration_csv(test::slurp(csv), csv.string());

  std::map<std::string, ByKind> frames;
  for (const analysis::PassObservation& o : set.passes) {
    EXPECT_TRUE(frames[o.frame].emplace(o.kind, o).second) << "one observation per frame and kind: " << o.frame;
    EXPECT_GE(o.ms, 0.0);
  }
  // Per method: which kinds its light frames drew, over the whole set.
  std::map<std::string, std::set<PassKind>> method_kinds;
  std::size_t depth_frames = 0;
  for (const auto& [frame, kinds] : frames) {
    const std::string method = frame.substr(frame.rfind(':') + 1);
    const bool light_frame = frame.find(":light") != std::string::npos;
    for (const auto& [kind, o] : kinds) {
      method_kinds[method].insert(kind);
      EXPECT_EQ(kind == PassKind::Depth, !light_frame) << frame;
    }
    if (!light_frame && frame.rfind("path:sweep3:", 0) == 0) ++depth_frames;
    if (light_frame) {
      EXPECT_TRUE(kinds.count(PassKind::Lit)) << frame << ": every light has its lit pass";
    }
    if (light_frame && method == "zpass") {
      EXPECT_TRUE(kinds.count(PassKind::Sides)) << frame;
      EXPECT_FALSE(kinds.count(PassKind::LightCap) || kinds.count(PassKind::DarkCap) || kinds.count(PassKind::NearCap))
          << frame << ": Z-pass draws no cap";
    }
    if (light_frame && method == "zfail") {
      EXPECT_TRUE(kinds.count(PassKind::LightCap) && kinds.count(PassKind::DarkCap)) << frame;
      EXPECT_FALSE(kinds.count(PassKind::NearCap)) << frame;
    }
  }
  EXPECT_EQ(depth_frames, 6u * 3u) << "six methods, three path frames";
  EXPECT_TRUE(method_kinds["atomiczp"].count(PassKind::Sides));
  EXPECT_FALSE(method_kinds["atomiczp"].count(PassKind::NearCap) || method_kinds["atomiczp"].count(PassKind::LightCap))
      << "AtomicZP draws its sides only; its eye-count pass has rows of its own";
  // AtomicZP's eye-count pass: one row per light frame it drew, fitted into
  // the profile's optional row.
  std::size_t eye_rows = 0;
  for (const analysis::EyeCountObservation& o : set.eye_count) {
    EXPECT_EQ(o.frame.substr(o.frame.rfind(':') + 1), "atomiczp") << o.frame;
    EXPECT_TRUE(frames.count(o.frame)) << o.frame << ": the frame's other passes are observed too";
    EXPECT_EQ(o.fragments, 32.0 * 24.0) << o.frame;
    EXPECT_GT(o.triangles, 0.0) << o.frame;
    eye_rows += o.frame.rfind("path:sweep3:", 0) == 0 ? 1 : 0;
  }
  EXPECT_EQ(eye_rows, 3u) << "one light in each of the three path frames";
  EXPECT_TRUE(written.device_profile->eye_count);
  // Every method frame drawn whole once more: one frame row each, its passes
  // observed, and the profile's frame row fitted from them.
  std::set<std::string> whole_frames;
  for (const analysis::FrameObservation& o : set.frames) {
    EXPECT_TRUE(whole_frames.insert(o.frame).second) << o.frame << ": one row per method frame";
    EXPECT_GT(o.ms, 0.0) << o.frame;
  }
  std::set<std::string> pass_frames;
  for (const auto& [frame, kinds] : frames) pass_frames.insert(analysis::frame_of_pass(frame));
  EXPECT_EQ(whole_frames, pass_frames) << "a frame row for every frame with pass rows, and only those";
  EXPECT_TRUE(written.device_profile->frame);
  EXPECT_TRUE(method_kinds["zpplus"].count(PassKind::NearCap));
  EXPECT_TRUE(method_kinds["zpplus-clipped-sides"].count(PassKind::NearCap));
  EXPECT_TRUE(method_kinds["zpplus-corrected"].count(PassKind::NearCap));

  // The last path frame against the emulation, drawn here again.
  analysis::CameraPath path = analysis::load_camera_path(path_.string());
  path.width = 32;
  path.height = 24;
  const Scene scene = parse_scene(analysis::path_frame_json(path, 2), "frame 2", ".");
  const std::string id = "path:sweep3:2";
  for (const auto& [method, projection, name] :
       {std::tuple{gl::ShadowMethod::ZFail, gl::LightProjection::Paper, "zfail"},
        std::tuple{gl::ShadowMethod::ZPPlus, gl::LightProjection::ClippedSides, "zpplus-clipped-sides"}}) {
    gl::EmulationSettings settings;
    settings.light_frustum.projection = projection;
    const gl::ShadowFrame f = gl::render_shadow_frame(scene, 0, method, settings);
    const ByKind& light = frames.at(id + ":light0:" + name);
    const ByKind& whole = frames.at(id + ":" + name);
    EXPECT_EQ(whole.at(PassKind::Depth).fragments, static_cast<double>(f.depth_pass.fragments)) << name;
    EXPECT_EQ(whole.at(PassKind::Depth).triangles, static_cast<double>(f.depth_pass.triangles)) << name;
    EXPECT_EQ(light.at(PassKind::Lit).fragments, static_cast<double>(f.depth_pass.fragments)) << name;
    double volume_fragments = 0, volume_triangles = 0;
    for (const PassKind k : {PassKind::Sides, PassKind::LightCap, PassKind::DarkCap})
      if (light.count(k)) {
        volume_fragments += light.at(k).fragments;
        volume_triangles += light.at(k).triangles;
      }
    EXPECT_EQ(volume_fragments, static_cast<double>(f.volume_pass.fragments)) << name;
    EXPECT_EQ(volume_triangles, static_cast<double>(f.volume_pass.triangles)) << name;
    if (method == gl::ShadowMethod::ZPPlus) {
      ASSERT_TRUE(light.count(PassKind::NearCap)) << "the near plane cuts the torus in the last frame";
      EXPECT_GT(f.cap_pass.fragments, 0u);
      EXPECT_EQ(light.at(PassKind::NearCap).fragments, static_cast<double>(f.cap_pass.fragments));
    }
  }

  // The noise floor's rows: Z-pass drawn again, the same frames and kinds.
  ASSERT_FALSE(set.again.empty());
  for (const analysis::PassObservation& o : set.again) {
    EXPECT_EQ(o.frame.substr(o.frame.rfind(':') + 1), "zpass");
    EXPECT_EQ(frames.at(o.frame).at(o.kind).fragments, o.fragments);
  }
  std::set<analysis::CpuTask> tasks;
  for (const analysis::CpuObservation& o : set.cpu) {
    tasks.insert(o.task);
    EXPECT_GT(o.triangles, 0.0) << o.frame;
  }
  EXPECT_EQ(tasks.size(), 3u) << "silhouettes, clipped-sides caps and the exact test";
}

TEST_F(CalibrateCommand, BadOptionsAreOneLineErrors) {
  const fs::path csv = dir_ / "c.csv";
  const std::string out = " --out '" + csv.string() + "'";
  const std::string policy = (fs::path(NEARCAP_SOURCE_DIR) / "data/policy.json").string();
  const std::pair<std::string, std::string> cases[] = {
      {"calibrate --samples 0" + out, "error (usage): nothing to calibrate on"},
      {"calibrate --samples 2", "--out"},
      {"calibrate --samples 2 --width 0" + out, "error (usage)"},
      {"calibrate --samples -3" + out, "error (usage)"},
      {"calibrate --samples 2 --policy '" + policy + "'" + out, "error (usage): --policy goes with --write-policy"},
      {"calibrate --samples 2 --policy '" + policy + "' --write-policy '" + policy + "'" + out,
       "error (usage): --write-policy"},
      {"calibrate --samples 2 --path '" + (dir_ / "missing.json").string() + "'" + out, "error (io)"},
      {"calibrate --samples 2 --out '" + dir_.string() + "'", "error (io)"},
      {"calibrate --samples 2 --write-policy '" + (dir_ / "p.json").string() + "' --policy '" +
           (dir_ / "none.json").string() + "'" + out,
       "error (io)"},
  };
  for (const auto& [args, says] : cases) {
    const test::CliResult r = test::run_cli(args, "calibrate_bad");
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
    EXPECT_NE(r.err.find(says), std::string::npos) << args << "\n" << r.err;
    EXPECT_EQ(r.err.rfind("nearcap: error (", 0), 0u) << args << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << "\n" << r.err;
    EXPECT_FALSE(fs::exists(csv)) << args;
  }
}

// One configuration leaves the held-out fifth without some pass kinds: the
// profile is written, and stderr names what it could not check.
TEST_F(CalibrateCommand, AProfileWithoutHeldOutObservationsIsWrittenWithAWarning) {
  const fs::path csv = dir_ / "c.csv", policy = dir_ / "p.json";
  const test::CliResult r = test::run_cli("calibrate --samples 1 --width 32 --height 24 --out '" + csv.string() +
                                              "' --write-policy '" + policy.string() + "'",
                                          "calibrate_one");
  if (r.exit_code == 2 && r.err.find("error (gl)") != std::string::npos)
    GTEST_SKIP() << "no headless OpenGL here: " << r.err;
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(policy));
  EXPECT_NE(r.err.find("calibrate: warning: no held-out observation of "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("fitted but unchecked"), std::string::npos) << r.err;
  // Each name it lists is a row the report printed with no held-out passes.
  const std::size_t at = r.err.find("observation of ") + 15;
  const std::string names = r.err.substr(at, r.err.find(':', at) - at);
  std::stringstream list(names);
  for (std::string name; std::getline(list, name, ',');) {
    if (name.front() == ' ') name.erase(0, 1);
    const std::size_t row = r.out.find("  " + name + " ", r.out.find("device profile for"));
    ASSERT_NE(row, std::string::npos) << name << "\n" << r.out;
    const std::string line = r.out.substr(row, r.out.find('\n', row) - row);
    EXPECT_NE(line.find(" / 0 "), std::string::npos) << line;
  }
}

// A set that never draws some pass kind or CPU task (the light in the near
// plane: no light frustum, no near-cap to test) gives those rows nothing to
// fit: no policy is written, and the error names them; the observations
// stay.
TEST_F(CalibrateCommand, NoPolicyWithARowNothingWasObservedFor) {
  const fs::path csv = dir_ / "c.csv", policy = dir_ / "p.json";
  const test::CliResult r =
      test::run_cli("calibrate --samples 4 --kinds light-in-near-plane --width 32 --height 24 --out '" + csv.string() +
                        "' --write-policy '" + policy.string() + "'",
                    "calibrate_unobserved");
  if (r.exit_code == 2 && r.err.find("error (gl)") != std::string::npos)
    GTEST_SKIP() << "no headless OpenGL here: " << r.err;
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("nearcap: error (usage): no training observation of "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("exact_test"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(policy));
  ASSERT_TRUE(fs::exists(csv));
  EXPECT_GT(fs::file_size(csv), 0u);
  // Each row it names is one the report printed with no training observation.
  const std::size_t at = r.err.find("no training observation of ") + 27;
  std::stringstream list(r.err.substr(at, r.err.find(':', at) - at));
  for (std::string name; std::getline(list, name, ',');) {
    if (name.front() == ' ') name.erase(0, 1);
    const std::size_t row = r.out.find("  " + name + " ", r.out.find("device profile for"));
    ASSERT_NE(row, std::string::npos) << name << "\n" << r.out;
    const std::string line = r.out.substr(row, r.out.find('\n', row) - row);
    EXPECT_NE(line.find("(0 / "), std::string::npos) << line;
  }
}

// A write that fails after the measuring (a full device passes the check made
// before it) is one error line; stdout names no file that was not written,
// and the observations, written first, outlive a failed policy write.
TEST_F(CalibrateCommand, AFailedWriteNamesNoUnwrittenFile) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full here";
  const fs::path csv = dir_ / "c.csv";
  const std::string run = "calibrate --samples 1 --width 32 --height 24 ";
  const test::CliResult full = test::run_cli(run + "--out /dev/full", "calibrate_full");
  if (full.exit_code == 2 && full.err.find("error (gl)") != std::string::npos)
    GTEST_SKIP() << "no headless OpenGL here: " << full.err;
  EXPECT_EQ(full.exit_code, 2) << full.err;
  EXPECT_NE(full.err.find("nearcap: error (io): /dev/full"), std::string::npos) << full.err;
  EXPECT_EQ(full.out.find("/dev/full"), std::string::npos) << full.out;

  const test::CliResult policy =
      test::run_cli(run + "--out '" + csv.string() + "' --write-policy /dev/full", "calibrate_policy_full");
  EXPECT_EQ(policy.exit_code, 2) << policy.err;
  EXPECT_NE(policy.err.find("nearcap: error (io): /dev/full"), std::string::npos) << policy.err;
  EXPECT_EQ(policy.out.find("policy with the device profile"), std::string::npos) << policy.out;
  EXPECT_NE(policy.out.find("observations in " + csv.string()), std::string::npos) << policy.out;
  ASSERT_TRUE(fs::exists(csv));
  EXPECT_GT(fs::file_size(csv), 0u);
}

}  // namespace
}  // namespace nearcap
