// The interactive viewer (nearcap view): its fly camera, its keys, its crack
// overlay, and the window itself under Xvfb, driven by a key script, its
// screenshot held against the headless render of the same frame.
#include <gtest/gtest.h>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wunused-function"
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#include <stb/stb_image.h>
#pragma GCC diagnostic pop

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "cli_support.hpp"
#include "nearcap/error.hpp"
#include "nearcap/exact/camera_space.hpp"
#include "nearcap/exact/crack_distance.hpp"
#include "nearcap/exact/pixel_reference.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/judge/crack_distances.hpp"
#include "nearcap/judge/crack_map.hpp"
#include "nearcap/view/crack_overlay.hpp"
#include "nearcap/view/fly_camera.hpp"
#include "nearcap/view/status_panel.hpp"
#include "nearcap/view/viewer_commands.hpp"

namespace nearcap {
namespace {

namespace fs = std::filesystem;
const std::string kData = std::string(NEARCAP_SOURCE_DIR) + "/data";

Vec3d camera_point(const Affine3d& view, const Vec3d& world) { return view.apply(world); }

TEST(FlyCamera, GivesTheSceneViewBackBitForBitUntilMoved) {
  const Scene scene = load_scene(kData + "/scenes/default.json");
  const view::FlyCamera camera(scene.camera.view, 0.1);
  EXPECT_EQ(camera.view().rows, scene.camera.view.rows);
  // Its eye is the point the view sends to the origin.
  const Vec3d origin = camera_point(scene.camera.view, camera.eye());
  EXPECT_NEAR(origin.x, 0, 1e-12);
  EXPECT_NEAR(origin.y, 0, 1e-12);
  EXPECT_NEAR(origin.z, 0, 1e-12);
}

TEST(FlyCamera, MovesAlongItsOwnAxesByItsStep) {
  const Scene scene = load_scene(kData + "/scenes/default.json");
  view::FlyCamera camera(scene.camera.view, 0.25);
  const Vec3d start = camera.eye();
  camera.move(2, 0, 0);  // two steps forward: the old eye is 0.5 behind, on the axis
  Vec3d p = camera_point(camera.view(), start);
  EXPECT_NEAR(p.x, 0, 1e-12);
  EXPECT_NEAR(p.y, 0, 1e-12);
  EXPECT_NEAR(p.z, 0.5, 1e-12);
  camera.move(-2, 1, -1);  // back, one step right and one down: the start is left and above
  p = camera_point(camera.view(), start);
  EXPECT_NEAR(p.x, -0.25, 1e-12);
  EXPECT_NEAR(p.y, 0.25, 1e-12);
  EXPECT_NEAR(p.z, 0, 1e-12);
  camera.scale_step(0.5);
  EXPECT_EQ(camera.step(), 0.125);
  EXPECT_THROW(view::FlyCamera(scene.camera.view, 0), Error);
}

TEST(FlyCamera, TurnsLeftAboutItsStartingUpAndUpAboutItsRight) {
  const Scene scene = load_scene(kData + "/scenes/default.json");
  view::FlyCamera camera(scene.camera.view, 1);
  const Affine3d v0 = scene.camera.view;
  const Vec3d up0{v0.rows[1][0], v0.rows[1][1], v0.rows[1][2]}, right0{v0.rows[0][0], v0.rows[0][1], v0.rows[0][2]};
  const Vec3d f0 = camera.forward();
  camera.turn(90, 0);  // a quarter turn left: forward becomes the old left
  EXPECT_NEAR(dot(camera.forward(), right0), -1, 1e-12);
  camera.turn(-90, 0);
  camera.turn(0, 30);  // look up: forward gains +sin 30 along the old up
  EXPECT_NEAR(dot(camera.forward(), up0), std::sin(M_PI / 6) + dot(f0, up0) * std::cos(M_PI / 6), 1e-12);
  camera.turn(0, -30);
  // Pitched, then yawed: the horizon stays level (right stays horizontal).
  camera.turn(0, 30);
  const double elevation = dot(camera.forward(), up0);
  camera.turn(90, 0);
  const Affine3d pitched = camera.view();
  const Vec3d right{pitched.rows[0][0], pitched.rows[0][1], pitched.rows[0][2]};
  EXPECT_NEAR(dot(right, up0), 0, 1e-12);
  EXPECT_NEAR(dot(camera.forward(), up0), elevation, 1e-12);  // turning left keeps the elevation
  camera.turn(-90, 0);
  camera.turn(0, -30);
  // 72 turns of 5 degrees: back where it started, the eye unmoved.
  for (int k = 0; k < 72; ++k) camera.turn(5, 0);
  const Affine3d v = camera.view();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) EXPECT_NEAR(v.rows[r][c], v0.rows[r][c], 1e-12) << r << "," << c;
}

TEST(ViewerKeys, ScriptsUseTheKeyTableAndNameAnUnknownKey) {
  const auto keys = view::parse_key_script("w, w left 3 c wait escape");
  ASSERT_EQ(keys.size(), 7u);
  EXPECT_EQ(keys[0].command, view::ViewerCommand::Forward);
  EXPECT_EQ(keys[2].command, view::ViewerCommand::TurnLeft);
  EXPECT_EQ(keys[3].command, view::ViewerCommand::PickMethod);
  EXPECT_EQ(keys[3].index, 2);
  EXPECT_EQ(keys[5].command, view::ViewerCommand::WaitForCracks);
  EXPECT_EQ(keys[6].command, view::ViewerCommand::Quit);
  try {
    view::parse_key_script("w w jump");
    FAIL() << "an unknown key was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Usage);
    EXPECT_NE(std::string(e.what()).find("key 3 'jump'"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(view::parse_key_script("").empty());
}

// The status fields wrapped to a width: no line wider, every field whole on
// one line where it fits, in order, and a field wider than a line broken
// at its spaces (a word wider than a line between characters).
TEST(StatusPanel, WrapsFieldsToTheWidthKeepingEachWholeWhereItFits) {
  const std::vector<std::string> fields = {"[m] zpplus-corrected", "[l] all lights", "12.3 ms (emulation 10.1, GL 2.2)",
                                           "[c] 1234 wrong px, 56 cracks (0.4 s)"};
  const int width = legend::text_width("[c] 1234 wrong px, 56 cracks (0.4 s)") + 3;
  const std::vector<std::string> lines = view::wrap_fields(fields, width);
  ASSERT_GE(lines.size(), 2u);
  std::string joined;
  for (const std::string& l : lines) {
    EXPECT_LE(legend::text_width(l), width) << l;
    joined += (joined.empty() ? "" : "  ") + l;
  }
  EXPECT_EQ(joined,
            "[m] zpplus-corrected  [l] all lights  12.3 ms (emulation 10.1, GL 2.2)  [c] 1234 wrong px, 56 "
            "cracks (0.4 s)");
  for (const std::string& f : fields)
    EXPECT_TRUE(
        std::any_of(lines.begin(), lines.end(), [&](const std::string& l) { return l.find(f) != std::string::npos; }))
        << f << " is split";
  // One line holds everything when it is wide enough.
  EXPECT_EQ(view::wrap_fields(fields, 100000).size(), 1u);
  // Narrower than a field: broken at its spaces, nothing lost.
  const std::vector<std::string> narrow = view::wrap_fields({"exact reference refused: a long reason"}, 60);
  std::string words;
  for (const std::string& l : narrow) {
    EXPECT_LE(legend::text_width(l), 60) << l;
    words += (words.empty() ? "" : " ") + l;
  }
  EXPECT_EQ(words, "exact reference refused: a long reason");
  // A word wider than a line: between characters, nothing lost.
  std::string chars;
  for (const std::string& l : view::wrap_fields({"abcdefghijklmnop"}, 20)) {
    EXPECT_LE(legend::text_width(l), 20) << l;
    chars += l;
  }
  EXPECT_EQ(chars, "abcdefghijklmnop");
  EXPECT_TRUE(view::wrap_fields({}, 100).empty());
}

// The overlay's counts and marks are the crack map's, light by light.
TEST(CrackOverlay, MarksWhatTheCrackMapJudges) {
  const Scene scene = load_scene(kData + "/scenes/eye_in_shadow.json");
  view::CrackOverlayJob job;
  job.frame_id = 7;
  job.scene = scene;
  job.frames.push_back(gl::render_shadow_frame(scene, 0, gl::ShadowMethod::ZPass));
  const view::CrackOverlayResult r = view::judge_overlay_job(job);
  EXPECT_EQ(r.frame_id, 7u);
  EXPECT_TRUE(r.error.empty()) << r.error;

  const CameraSpaceScene cs(scene);
  const PixelReferenceTracer tracer(cs, 0);
  const PixelReference ref = compute_pixel_reference(tracer);
  CrackReport report = judge_frame(job.frames[0], ref);
  CrackDistances(tracer, ref).measure(report);
  EXPECT_GT(report.wrong, 1000u);  // Z-pass with the eye in shadow
  EXPECT_EQ(r.wrong, report.wrong);
  EXPECT_EQ(r.cracks, *report.cracks);
  std::size_t marked = 0, cracks = 0;
  for (const view::OverlayMark m : r.marks) {
    marked += m != view::OverlayMark::None;
    cracks += m == view::OverlayMark::CrackLit || m == view::OverlayMark::CrackShadowed;
  }
  EXPECT_EQ(marked, report.wrong);
  EXPECT_EQ(cracks, *report.cracks);

  // Painted: every marked pixel changes, and nothing far from a mark does.
  legend::Image image{
      scene.camera.width, scene.camera.height,
      std::vector<std::uint8_t>(3 * static_cast<std::size_t>(scene.camera.width) * scene.camera.height, 128)};
  view::paint_overlay(image, r);
  std::size_t changed = 0;
  for (std::size_t p = 0; p < r.marks.size(); ++p) {
    const int i = static_cast<int>(p % scene.camera.width), j = static_cast<int>(p / scene.camera.width);
    const std::size_t top = static_cast<std::size_t>(scene.camera.height - 1 - j) * scene.camera.width + i;
    const bool differs = image.rgb[3 * top] != 128 || image.rgb[3 * top + 1] != 128 || image.rgb[3 * top + 2] != 128;
    if (r.marks[p] != view::OverlayMark::None) {
      EXPECT_TRUE(differs) << "marked pixel " << i << "," << j;
    }
    changed += differs;
  }
  EXPECT_GE(changed, marked);
}

TEST(CrackOverlay, TheWorkerEndsOnTheNewestJob) {
  const Scene scene = load_scene(kData + "/scenes/room.json");
  view::CrackOverlay worker;
  for (std::uint64_t id = 1; id <= 3; ++id) {
    view::CrackOverlayJob job;
    job.frame_id = id;
    job.scene = scene;
    job.frames.push_back(gl::render_shadow_frame(scene, 0, gl::ShadowMethod::ZFail));
    worker.start(std::move(job));
  }
  const auto last = worker.wait();
  ASSERT_TRUE(last.has_value());
  EXPECT_EQ(last->frame_id, 3u);
  EXPECT_FALSE(worker.busy());
}

// ---- the window, under Xvfb ------------------------------------------------

struct Png {
  int width = 0, height = 0;
  std::vector<unsigned char> rgb;
};

Png read_png(const fs::path& p) {
  Png out;
  int channels = 0;
  unsigned char* data = stbi_load(p.string().c_str(), &out.width, &out.height, &channels, 3);
  if (data) {
    out.rgb.assign(data, data + 3 * static_cast<std::size_t>(out.width) * out.height);
    stbi_image_free(data);
  }
  return out;
}

class ViewCommand : public ::testing::Test {
 protected:
  void SetUp() override {
    if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0)
      GTEST_SKIP() << "xvfb-run is not installed (scripts/install-deps.sh installs xvfb): the viewer needs a display";
    dir_ = fs::temp_directory_path() / ("nearcap_view_test_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    if (!dir_.empty()) fs::remove_all(dir_);
  }
  test::CliResult view(const std::string& args) {
    return test::run_cli("view " + args, "view", "xvfb-run -a -s '-screen 0 1280x720x24'");
  }
  fs::path dir_;
};

TEST_F(ViewCommand, ScreenshotAfterAKeyScriptIsTheHeadlessRenderOfTheSavedView) {
  const fs::path shot = dir_ / "shot.png";
  // Fly, turn, switch to the second method, hide the status line, save the view.
  const auto r = view("data/scenes/default.json --method zpass,zpplus-corrected --keys 'w w a left up m h p' --out '" +
                      dir_.string() + "' --screenshot '" + shot.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("saved " + (dir_ / "view-000.json").string()), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("zpplus-corrected"), std::string::npos) << r.out;
  const auto rendered = test::run_cli("render '" + (dir_ / "view-000.json").string() +
                                          "' --method zpplus-corrected --out '" + (dir_ / "render").string() + "'",
                                      "view_render");
  ASSERT_EQ(rendered.exit_code, 0) << rendered.err;
  const Png a = read_png(shot), b = read_png(dir_ / "render" / "frame-zpplus-corrected.png");
  ASSERT_EQ(a.width, 640);
  ASSERT_EQ(a.height, 480);
  ASSERT_EQ(b.width, a.width);
  ASSERT_EQ(b.height, a.height);
  std::size_t differ = 0;
  for (std::size_t k = 0; k < a.rgb.size(); ++k) differ += a.rgb[k] != b.rgb[k];
  EXPECT_EQ(differ, 0u);
  // The saved view is not the scene file's view: the keys moved the camera.
  const auto saved = nlohmann::json::parse(test::slurp(dir_ / "view-000.json"));
  EXPECT_TRUE(saved["camera"].contains("view"));
  const Png start = [&] {
    const auto s = test::run_cli(
        "render data/scenes/default.json --method zpplus-corrected --out '" + (dir_ / "start").string() + "'",
        "view_render");
    EXPECT_EQ(s.exit_code, 0) << s.err;
    return read_png(dir_ / "start" / "frame-zpplus-corrected.png");
  }();
  EXPECT_NE(start.rgb, a.rgb);
}

// Escape played by --keys quits as the key does: the keys before it run
// (the view saved), none after it.
TEST_F(ViewCommand, EscapeInAKeyScriptQuits) {
  const auto r =
      test::run_cli("view data/scenes/default.json --method zpass --keys 'w p escape p' --out '" + dir_.string() + "'",
                    "view", "timeout 120 xvfb-run -a -s '-screen 0 1280x720x24'");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir_ / "view-000.json"));
  EXPECT_FALSE(fs::exists(dir_ / "view-001.json"));
  // With --screenshot, the view at escape is the screenshot.
  const fs::path shot = dir_ / "shot.png";
  const auto s = test::run_cli(
      "view data/scenes/default.json --method zpass --keys 'w escape' --screenshot '" + shot.string() + "'", "view",
      "timeout 120 xvfb-run -a -s '-screen 0 1280x720x24'");
  EXPECT_EQ(s.exit_code, 0) << s.err;
  EXPECT_TRUE(fs::exists(shot));
}

// A view saved by the p key never takes the screenshot's file, also where
// --screenshot names it through a link that does not resolve yet.
TEST_F(ViewCommand, ASavedViewNeverTakesTheScreenshotsFile) {
  const fs::path link = dir_ / "shot-link.png";
  fs::create_symlink(dir_ / "view-000.json", link);
  const auto r = view("data/scenes/default.json --method zpass --keys p --out '" + dir_.string() + "' --screenshot '" +
                      link.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("saved " + (dir_ / "view-001.json").string()), std::string::npos) << r.out;
  EXPECT_EQ(test::slurp(dir_ / "view-000.json").rfind("\x89PNG", 0), 0u);
  EXPECT_TRUE(nlohmann::json::parse(test::slurp(dir_ / "view-001.json")).contains("camera"));
}

TEST_F(ViewCommand, TheStatusLineCoversOnlyTheTopOfTheFrame) {
  const fs::path with = dir_ / "with.png", without = dir_ / "without.png";
  ASSERT_EQ(view("data/scenes/default.json --method policy --screenshot '" + with.string() + "'").exit_code, 0);
  ASSERT_EQ(view("data/scenes/default.json --method policy --keys h --screenshot '" + without.string() + "'").exit_code,
            0);
  const Png a = read_png(with), b = read_png(without);
  ASSERT_EQ(a.rgb.size(), b.rgb.size());
  ASSERT_FALSE(a.rgb.empty());
  int lowest = -1;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < 3 * a.width; ++x)
      if (a.rgb[3 * static_cast<std::size_t>(y) * a.width + x] != b.rgb[3 * static_cast<std::size_t>(y) * b.width + x])
        lowest = y;
  EXPECT_GT(lowest, 8);   // the status line is there
  EXPECT_LE(lowest, 26);  // at 640 pixels, two lines of 12 pixels (the policy's methods per occluder) and a margin
}

// In a window narrower than the status line (room.json: 320 pixels), the
// status wraps and every field is in the window, the crack count included:
// the screenshot is the headless render of the same frame with the status
// printed on stdout painted over it, wrapped (Z-fail leaves no wrong pixel
// on room.json, so the overlay marks none).
TEST_F(ViewCommand, TheStatusLineWrapsAndShowsTheCrackCountInTheWindow) {
  const fs::path shot = dir_ / "shot.png";
  const auto r = view("data/scenes/room.json --method zfail --keys 'c wait' --screenshot '" + shot.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // "screenshot FILE (320x240): FIELD  FIELD  ..."
  const std::string marker = "(320x240): ";
  const auto at = r.out.find(marker);
  ASSERT_NE(at, std::string::npos) << r.out;
  std::string status = r.out.substr(at + marker.size());
  status = status.substr(0, status.find('\n'));
  ASSERT_NE(status.find(" 0 wrong px, 0 cracks"), std::string::npos) << status;
  std::vector<std::string> fields;
  for (std::size_t from = 0;;) {
    const std::size_t gap = status.find("  ", from);
    fields.push_back(status.substr(from, gap - from));
    if (gap == std::string::npos) break;
    from = gap + 2;
  }
  ASSERT_EQ(fields.size(), 4u) << status;
  const int scale = view::status_scale(320);
  EXPECT_GT(legend::text_width(status) * scale, 320) << "the status line fits on one line: nothing to wrap";
  const auto rendered =
      test::run_cli("render data/scenes/room.json --method zfail --out '" + (dir_ / "render").string() + "'", "view");
  ASSERT_EQ(rendered.exit_code, 0) << rendered.err;
  const Png a = read_png(shot), b = read_png(dir_ / "render" / "frame-zfail.png");
  ASSERT_EQ(a.width, 320);
  ASSERT_EQ(a.height, 240);
  ASSERT_EQ(b.rgb.size(), a.rgb.size());
  legend::Image expected{b.width, b.height, b.rgb};
  const int band = view::paint_status(expected, {fields});
  EXPECT_GE(band, 2 * 12 * scale);  // wrapped: more than one line
  std::size_t differ = 0;
  for (std::size_t k = 0; k < a.rgb.size(); ++k) differ += a.rgb[k] != expected.rgb[k];
  EXPECT_EQ(differ, 0u);
}

TEST_F(ViewCommand, TheCrackOverlayCountsWhatRenderCompareCounts) {
  const fs::path shot = dir_ / "cracks.png";
  const auto r =
      view("data/scenes/eye_in_shadow.json --method zpass --keys 'c wait' --screenshot '" + shot.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // "... [c] N wrong px, M cracks (...)"
  const auto at = r.out.find("[c] ");
  ASSERT_NE(at, std::string::npos) << r.out;
  std::size_t used = 0;
  const unsigned long wrong = std::stoul(r.out.substr(at + 4), &used);
  const auto comma = r.out.find(" wrong px, ", at);
  ASSERT_NE(comma, std::string::npos) << r.out;
  const unsigned long cracks = std::stoul(r.out.substr(comma + 11));
  const auto compare =
      test::run_cli("render data/scenes/eye_in_shadow.json --light 0 --method zpass --compare", "view");
  ASSERT_EQ(compare.exit_code, 0) << compare.err;
  const auto record = nlohmann::json::parse(compare.out)["methods"][0];
  EXPECT_GT(record["gl_vs_exact"].get<std::size_t>(), 1000u);
  EXPECT_EQ(wrong, record["gl_vs_exact"].get<std::size_t>());
  EXPECT_EQ(cracks, record["cracks"].get<std::size_t>());
}

TEST(ViewCommandErrors, NoDisplayIsOneLineNamingXvfb) {
  const auto r = test::run_cli("view data/scenes/room.json", "view_nodisplay", "env -u DISPLAY -u WAYLAND_DISPLAY");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("needs a display"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("xvfb-run"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

TEST(ViewCommandErrors, AnUnknownKeyIsAUsageErrorBeforeAnyWindow) {
  const auto r =
      test::run_cli("view data/scenes/room.json --keys 'w fly'", "view_badkey", "env -u DISPLAY -u WAYLAND_DISPLAY");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("key 2 'fly'"), std::string::npos) << r.err;
  const auto step =
      test::run_cli("view data/scenes/room.json --step -1", "view_badstep", "env -u DISPLAY -u WAYLAND_DISPLAY");
  EXPECT_EQ(step.exit_code, 2) << step.err;
  EXPECT_NE(step.err.find("--step: must be a positive distance"), std::string::npos) << step.err;
}

}  // namespace
}  // namespace nearcap
