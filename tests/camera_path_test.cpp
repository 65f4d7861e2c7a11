// Camera paths (analysis/camera_path.hpp) and `nearcap frame`: the bundled
// paths load and every frame is a scene; keyframes are hit exactly, near
// planes interpolate geometrically; the near-plane sweep meets cases C and D;
// the eye-in-shadow paths stay in the shadow;
// a malformed path names the file and the field.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <limits>

#include "cli_support.hpp"
#include "nearcap/analysis/camera_path.hpp"
#include "nearcap/error.hpp"
#include "nearcap/exact/classification.hpp"
#include "nearcap/exact/near_cap.hpp"
#include "nearcap/io/scene_file.hpp"

namespace nearcap {
namespace {

namespace fs = std::filesystem;
const std::string kPaths = std::string(NEARCAP_SOURCE_DIR) + "/data/paths/";

TEST(CameraPath, EveryBundledPathLoadsAndItsFramesAreScenes) {
  std::size_t paths = 0;
  for (const auto& entry : fs::directory_iterator(kPaths)) {
    const analysis::CameraPath path = analysis::load_camera_path(entry.path().string());
    ++paths;
    SCOPED_TRACE(entry.path().string());
    EXPECT_FALSE(path.description.empty());
    EXPECT_GE(path.frames, 10);
    for (int f : {0, path.frames / 3, path.frames - 1}) {
      const Scene scene = parse_scene(analysis::path_frame_json(path, f), "frame", ".");
      EXPECT_EQ(scene.camera.width, path.width);
    }
    // The first and last frames are the first and last keyframes, exactly.
    const analysis::CameraKeyframe first = analysis::path_camera(path, 0);
    const analysis::CameraKeyframe last = analysis::path_camera(path, path.frames - 1);
    EXPECT_EQ(first.eye.x, path.keyframes.front().eye.x);
    EXPECT_EQ(last.eye.z, path.keyframes.back().eye.z);
    EXPECT_EQ(last.near, path.keyframes.back().near);
  }
  EXPECT_GE(paths, 7u);
}

TEST(CameraPath, NearPlanesInterpolateGeometrically) {
  const analysis::CameraPath zoom = analysis::load_camera_path(kPaths + "zoom.json");
  ASSERT_EQ(zoom.keyframes.size(), 2u);
  ASSERT_EQ(zoom.frames % 2, 0);
  // Halfway in t between frames frames/2 - 1 and frames/2 is the geometric mean.
  const double t = (zoom.frames / 2 - 1) / double(zoom.frames - 1);
  const double expected = zoom.keyframes[0].near * std::pow(zoom.keyframes[1].near / zoom.keyframes[0].near, t);
  EXPECT_NEAR(analysis::path_camera(zoom, zoom.frames / 2 - 1).near, expected, 1e-15);
  EXPECT_GT(analysis::path_camera(zoom, 30).near, 0.001);
  EXPECT_LT(analysis::path_camera(zoom, 30).near, 0.1);
}

TEST(CameraPath, TheNearPlaneSweepMeetsCasesCAndD) {
  const analysis::CameraPath path = analysis::load_camera_path(kPaths + "near_plane_sweep.json");
  std::array<std::size_t, kQuadCaseCount> frames_with{};
  for (int f = 0; f < path.frames; ++f) {
    const Scene scene = parse_scene(analysis::path_frame_json(path, f), "frame", ".");
    const CameraSpaceScene cs(scene);
    std::array<std::size_t, kQuadCaseCount> counts{};
    const SceneClassification classification = classify_scene(cs);  // kept: the loop reads into it
    for (const ObjectClassification& o : classification.lights[0].objects)
      for (std::size_t c = 0; c < kQuadCaseCount; ++c) counts[c] += o.case_counts[c];
    for (std::size_t c = 0; c < kQuadCaseCount; ++c) frames_with[c] += counts[c] > 0;
  }
  EXPECT_GT(frames_with[static_cast<int>(QuadCase::C1)], 0u);
  EXPECT_GT(frames_with[static_cast<int>(QuadCase::C2)], 0u);
  EXPECT_GT(frames_with[static_cast<int>(QuadCase::D)], 0u);
  EXPECT_LT(frames_with[static_cast<int>(QuadCase::D)], static_cast<std::size_t>(path.frames)) << "D is rare";
}

class BadPath : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("nearcap_paths_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  void expect_error(const std::string& text, const std::string& fragment) {
    const std::string file = (dir_ / "p.json").string();
    std::ofstream(file) << text;
    try {
      (void)analysis::load_camera_path(file);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  }
  fs::path dir_;
};

TEST_F(BadPath, NamesTheFileAndTheField) {
  const std::string scene = "\"scene\": \"" + std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/room.json\"";
  const std::string key = "{\"eye\": [0, 2, 5], \"target\": [0, 2, 0]}";
  expect_error("{" + scene + ", \"frames\": 10}", "keyframes");
  expect_error("{" + scene + ", \"frames\": 0, \"keyframes\": [" + key + "]}", "frames");
  expect_error("{" + scene + ", \"frames\": 10, \"keyframes\": [" + key + "], \"speed\": 2}", "speed: unknown key");
  expect_error("{" + scene + ", \"frames\": 10, \"keyframes\": [{\"eye\": [0, 2, 5]}]}", "keyframes[0]");
  expect_error("{" + scene +
                   ", \"frames\": 10, \"keyframes\": [{\"eye\": [0, 2, 5], \"target\": [0, 2, 0], "
                   "\"near\": -1}]}",
               "keyframes[0].near");
  expect_error("{\"scene\": \"missing.json\", \"frames\": 10, \"keyframes\": [" + key + "]}", "missing.json");
  expect_error("{\"scene\": \"\", \"frames\": 10, \"keyframes\": [" + key + "]}", "scene: an empty file name");
  expect_error("{\"frames\": 10,", "malformed JSON");
}

// Keyframes whose values are too far apart to interpolate in double: a range
// error naming the frame, the keyframes and the field, not a scene field the
// user never wrote.
TEST_F(BadPath, KeyframesInterpolatingPastDoublesRangeAreARangeError) {
  const std::string scene = "\"scene\": \"" + std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/room.json\"";
  const std::string file = (dir_ / "far.json").string();
  for (const auto& [keys, field] :
       {std::pair<std::string, std::string>{"{\"eye\": [1e308, 2, 3], \"target\": [0, 0, 0]}, "
                                            "{\"eye\": [-1e308, 2, 3], \"target\": [0, 0, 0]}",
                                            "eye"},
        {"{\"eye\": [0, 2, 5], \"target\": [0, 2, 0], \"near\": 5e-324}, "
         "{\"eye\": [0, 2, 6], \"target\": [0, 2, 0], \"near\": 50}",
         "near"}}) {
    std::ofstream(file) << "{" + scene + ", \"frames\": 3, \"keyframes\": [" + keys + "]}";
    const analysis::CameraPath path = analysis::load_camera_path(file);
    try {
      (void)analysis::path_frame_json(path, 1);
      ADD_FAILURE() << "frame 1 of " << keys;
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), ErrorKind::Range) << e.what();
      EXPECT_EQ(std::string(e.what()), file + ": frame 1: keyframes 0 and 1 interpolate past double's range in " +
                                           field + " (their values are too far apart)");
    }
  }
}

// The two eye-in-shadow paths keep the eye inside the torus's shadow volume:
// the near-cap has no face of count 0 (the near rectangle lies wholly in the
// shadow), on frames along the whole path, so Z-pass is wrong on every frame
// as their descriptions say.
TEST(CameraPath, TheEyeInShadowPathsKeepTheEyeInTheShadow) {
  for (const char* name : {"eye_in_shadow.json", "looking_away.json"}) {
    const analysis::CameraPath path = analysis::load_camera_path(kPaths + name);
    for (int f : {0, path.frames / 4, path.frames / 2, 3 * path.frames / 4, path.frames - 1}) {
      const Scene scene = parse_scene(analysis::path_frame_json(path, f), "frame", ".");
      const NearCap cap = NearCap::build(CameraSpaceScene(scene), 0);
      std::size_t min_count = std::numeric_limits<std::size_t>::max();
      for (const NearCapFace& face : cap.faces()) min_count = std::min(min_count, face.count);
      EXPECT_GE(min_count, 1u) << name << " frame " << f << ": part of the near rectangle is lit";
    }
  }
}

TEST(FrameCommand, WritesAFrameTheOtherCommandsAccept) {
  const fs::path out = fs::temp_directory_path() / ("nearcap_frame_" + std::to_string(::getpid()) + ".json");
  const test::CliResult r =
      test::run_cli("frame data/paths/near_plane_sweep.json --frame 31 --out " + out.string(), "frame");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const test::CliResult c = test::run_cli("classify --json " + out.string(), "frame_classify");
  ASSERT_EQ(c.exit_code, 0) << c.err;
  EXPECT_NE(c.out.find("\"D\":6"), std::string::npos) << "frame 31 is the one with case D";
  fs::remove(out);
  const test::CliResult bad = test::run_cli("frame data/paths/near_plane_sweep.json --frame 60", "frame_bad");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("the path has 60 frames"), std::string::npos) << bad.err;
}

}  // namespace
}  // namespace nearcap
