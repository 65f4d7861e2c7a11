// What the command line hands a person: crack images of one width per frame
// size whose legend names the method that drew them, the near-cap SVG at the
// frame's aspect with its caption whole, render --compare as a table, the
// help, and a mesh that cannot be opened named as written and as resolved.
//
// Plain string scanning, no <regex>: libstdc++'s regex executor recurses per
// character and overflows the stack on an SVG's long path data under the
// sanitizers (and GCC 12 warns inside it there).
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cli_support.hpp"
#include "nearcap/judge/legend.hpp"
#include "nearcap/judge/near_cap_svg.hpp"

namespace nearcap {
namespace {

namespace fs = std::filesystem;

std::uint32_t be32(const std::string& bytes, std::size_t at) {
  std::uint32_t v = 0;
  for (std::size_t k = 0; k < 4; ++k) v = (v << 8) | static_cast<unsigned char>(bytes[at + k]);
  return v;
}

struct PngInfo {
  std::uint32_t width = 0, height = 0;
  std::map<std::string, std::string> text;  // tEXt chunks: keyword -> text
};

// The PNG's size from its IHDR, and its tEXt chunks.
PngInfo png_info(const std::string& png) {
  PngInfo info;
  EXPECT_GT(png.size(), 33u);
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  if (png.size() < 33) return info;
  EXPECT_EQ(png.substr(12, 4), "IHDR");
  info.width = be32(png, 16);
  info.height = be32(png, 20);
  for (std::size_t at = 8; at + 12 <= png.size();) {
    const std::uint32_t length = be32(png, at);
    const std::string type = png.substr(at + 4, 4);
    if (type == "tEXt") {
      const std::string data = png.substr(at + 8, length);
      const std::size_t nul = data.find('\0');
      if (nul != std::string::npos) info.text[data.substr(0, nul)] = data.substr(nul + 1);
    }
    at += 12 + static_cast<std::size_t>(length);
  }
  return info;
}

class CliOutputs : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("nearcap_outputs_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

// Every crack image of a frame is as wide as the frame, however long its
// legend's lines (the policy's, raytrace's): the legend wraps instead.
TEST_F(CliOutputs, CrackImagesOfOneFrameSizeHaveOneWidth) {
  const test::CliResult r = test::run_cli(
      "cracks data/scenes/case_d.json --light 0 --method all --out '" + dir_.string() + "'", "outputs_widths");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::size_t images = 0;
  for (const auto& e : fs::directory_iterator(dir_)) {
    if (e.path().extension() != ".png") continue;
    ++images;
    const PngInfo png = png_info(test::slurp(e.path()));
    EXPECT_EQ(png.width, 640u) << e.path().filename() << ": the frame is 640 wide";
    EXPECT_GT(png.height, 480u) << e.path().filename() << ": the legend below the frame";
  }
  EXPECT_GE(images, 6u) << "the five methods and the policy (and raytrace where built)";
}

// A frame narrower than the narrowest legend: padded to that width, the same
// for every method.
TEST_F(CliOutputs, CrackImagesOfASmallFrameArePaddedToOneWidth) {
  const fs::path scene = dir_ / "small.json";
  nlohmann::json j = nlohmann::json::parse(test::slurp(fs::path(NEARCAP_SOURCE_DIR) / "data/scenes/case_d.json"));
  j["camera"]["width"] = 64;
  j["camera"]["height"] = 48;
  for (auto& o : j["objects"])
    o["mesh"] =
        (fs::path(NEARCAP_SOURCE_DIR) / "data/scenes" / o["mesh"].get<std::string>()).lexically_normal().string();
  std::ofstream(scene) << j.dump();
  const test::CliResult r = test::run_cli(
      "cracks '" + scene.string() + "' --light 0 --method zpass,zfail,policy --out '" + (dir_ / "out").string() + "'",
      "outputs_small");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* name : {"cracks-zpass.png", "cracks-zfail.png", "cracks-policy.png"})
    EXPECT_EQ(png_info(test::slurp(dir_ / "out" / name)).width, static_cast<std::uint32_t>(legend::kMinLegendWidth))
        << name;
}

// The policy's crack image says "policy" and what it ran on the occluders,
// as the record's occluders say.
TEST_F(CliOutputs, ThePolicysLegendNamesThePolicyAndItsMethods) {
  const test::CliResult r = test::run_cli(
      "cracks data/scenes/case_d.json --light 0 --method zfail,policy --out '" + dir_.string() + "'", "outputs_policy");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  const nlohmann::json& policy = j.at("methods").at(1);
  ASSERT_EQ(policy.at("method"), "policy");
  ASSERT_EQ(policy.at("occluders").size(), 1u);
  const std::string ran = policy["occluders"][0]["method"].get<std::string>();
  const std::string title = png_info(test::slurp(dir_ / "cracks-policy.png")).text["Title"];
  EXPECT_EQ(title.rfind("policy (" + ran + " on 1 occluder): ", 0), 0u) << title;
  EXPECT_NE(title.find(std::to_string(policy.at("wrong").get<std::size_t>()) + " wrong"), std::string::npos) << title;
  const std::string zfail = png_info(test::slurp(dir_ / "cracks-zfail.png")).text["Title"];
  EXPECT_EQ(zfail.rfind("zfail: ", 0), 0u) << zfail;
}

// Numbers of an SVG attribute list: -?digits(.digits)?
std::vector<double> numbers(const std::string& s) {
  std::vector<double> v;
  const auto digit = [&s](std::size_t k) { return k < s.size() && s[k] >= '0' && s[k] <= '9'; };
  for (std::size_t k = 0; k < s.size();) {
    const std::size_t start = k;
    if (s[k] == '-' && digit(k + 1)) ++k;
    if (!digit(k)) {
      k = start + 1;
      continue;
    }
    while (digit(k)) ++k;
    if (k < s.size() && s[k] == '.' && digit(k + 1)) {
      ++k;
      while (digit(k)) ++k;
    }
    v.push_back(std::stod(s.substr(start, k - start)));
  }
  return v;
}

// The value of ` name="..."` in an element's text, or "" without one.
std::string attribute(const std::string& element, const std::string& name) {
  const std::string key = " " + name + "=\"";
  const std::size_t at = element.find(key);
  if (at == std::string::npos) return {};
  const std::size_t begin = at + key.size(), end = element.find('"', begin);
  return end == std::string::npos ? std::string() : element.substr(begin, end - begin);
}

// Each element's text `<TAG ...>` in document order.
std::vector<std::string> elements(const std::string& svg, const std::string& tag) {
  std::vector<std::string> out;
  for (std::size_t at = svg.find("<" + tag + " "); at != std::string::npos; at = svg.find("<" + tag + " ", at + 1)) {
    const std::size_t end = svg.find('>', at);
    if (end == std::string::npos) break;
    out.push_back(svg.substr(at, end - at + 1));
  }
  return out;
}

// The near-cap picture of a 640 x 480 frame whose near rectangle is square
// (non-square pixels): drawn at 4:3 like the frame's images, its faces
// filling that rectangle, its caption whole and within the picture's width.
TEST_F(CliOutputs, TheNearCapSvgHasTheFramesAspectAndItsWholeCaption) {
  const fs::path svg_file = dir_ / "cap.svg";
  const test::CliResult r = test::run_cli(
      "cap data/scenes/near_cap_bunny_silhouettes.json --light 0 --svg '" + svg_file.string() + "'", "outputs_svg");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string svg = test::slurp(svg_file);
  const std::vector<std::string> roots = elements(svg, "svg");
  ASSERT_FALSE(roots.empty()) << svg.substr(0, 200);
  const std::string& root = roots.front();
  const std::vector<double> view_box = numbers(attribute(root, "viewBox"));
  ASSERT_EQ(view_box.size(), 4u) << root;
  const double width = view_box[2];
  EXPECT_EQ(std::stod(attribute(root, "width")), width);
  EXPECT_EQ(std::stod(attribute(root, "height")), view_box[3]);

  // The faces' extent: the whole near rectangle, at 640:480.
  double max_x = 0, max_y = 0;
  for (const std::string& path : elements(svg, "path")) {
    const std::vector<double> v = numbers(attribute(path, "d"));
    for (std::size_t k = 0; k + 1 < v.size(); k += 2) {
      max_x = std::max(max_x, v[k]);
      max_y = std::max(max_y, v[k + 1]);
    }
  }
  // The SVG writes coordinates to 3 decimals (near_cap_svg.cpp): each is
  // within 5e-4 of its value, so max_x within 1e-2 of the width and, with
  // max_y about 480, the ratio within 1e-4 of 640/480 leave room to spare.
  EXPECT_NEAR(max_x, width, 1e-2);
  EXPECT_NEAR(max_x / max_y, 640.0 / 480.0, 1e-4) << "the picture has the frame's aspect";
  EXPECT_GT(view_box[3], max_y) << "the legend below the picture";

  // The caption: every line within the width (glyphs counted at DejaVu Sans's
  // widest of their class), and together the whole text.
  std::string caption;
  std::size_t lines = 0;
  const std::string opening = "<text class=\"caption\" x=\"";
  for (std::size_t at = svg.find(opening); at != std::string::npos; at = svg.find(opening, at + 1), ++lines) {
    const std::size_t x_end = svg.find('"', at + opening.size());
    const std::size_t text_begin = svg.find('>', at) + 1, text_end = svg.find('<', text_begin);
    ASSERT_NE(text_end, std::string::npos);
    ASSERT_EQ(svg.compare(text_end, 7, "</text>"), 0) << svg.substr(at, 200);
    const double x = std::stod(svg.substr(at + opening.size(), x_end - at - opening.size()));
    const std::string line = svg.substr(text_begin, text_end - text_begin);
    EXPECT_LE(x + caption_width(line), width) << line;
    caption += (caption.empty() ? "" : " ") + line;
  }
  EXPECT_GE(lines, 1u);
  EXPECT_EQ(caption.rfind("data/scenes/near_cap_bunny_silhouettes.json, light 0; drawn to the frame's aspect", 0), 0u)
      << caption;
  EXPECT_NE(caption.find("(pixel aspect 0.75)"), std::string::npos) << caption;
}

TEST(CaptionWrap, LinesFitAndKeepEveryWord) {
  const std::string text =
      "data/scenes/near_cap_bunny_silhouettes.json, light 0; drawn to the frame's aspect (640x480 pixels); the "
      "near rectangle's own aspect is 1, so its pixels are not square (pixel aspect 0.75) WWWWWWWWWWWWWWWWWWWWWWWWWWWW";
  for (const double width : {100.0, 300.0, 780.0}) {
    const std::vector<std::string> lines = wrap_caption(text, width);
    EXPECT_GT(lines.size(), 1u);
    std::string rejoined;
    for (const std::string& l : lines) {
      EXPECT_LE(caption_width(l), width) << l;
      rejoined += l;
    }
    // Every character but the spaces where lines break, in order.
    auto without_spaces = [](std::string s) {
      s.erase(std::remove(s.begin(), s.end(), ' '), s.end());
      return s;
    };
    EXPECT_EQ(without_spaces(rejoined), without_spaces(text)) << width;
  }
  EXPECT_EQ(caption_width("W"), 12);
  EXPECT_EQ(caption_width("i"), 5.5);
}

// `nearcap`, `nearcap help` and `nearcap help CMD` print help and succeed.
TEST(CliHelp, NoSubcommandAndHelpPrintTheHelp) {
  for (const char* args : {"", "help"}) {
    const test::CliResult r = test::run_cli(args, "outputs_help");
    EXPECT_EQ(r.exit_code, 0) << "'" << args << "': " << r.err;
    EXPECT_NE(r.out.find("cracks"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("nearcap: exact and float analysis"), std::string::npos) << r.out;
    EXPECT_TRUE(r.err.empty()) << r.err;
  }
  const test::CliResult cracks = test::run_cli("help cracks", "outputs_help");
  EXPECT_EQ(cracks.exit_code, 0) << cracks.err;
  EXPECT_NE(cracks.out.find("--method"), std::string::npos) << cracks.out;
  EXPECT_NE(cracks.out.find("\nUsage: nearcap cracks [OPTIONS] scene\n"), std::string::npos) << cracks.out;
  const test::CliResult bogus = test::run_cli("help bogus", "outputs_help");
  EXPECT_EQ(bogus.exit_code, 2);
  EXPECT_EQ(bogus.err.rfind("nearcap: error (usage): no help on 'bogus'", 0), 0u) << bogus.err;
}

// The view's summary in `nearcap --help` is one short line; its keys are in
// `view --help`.
TEST(CliHelp, ViewsSummaryIsShortAndItsKeysAreInItsOwnHelp) {
  const test::CliResult r = test::run_cli("--help", "outputs_help");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::istringstream lines(r.out);
  std::string line, view;
  while (std::getline(lines, line))
    if (line.rfind("  view ", 0) == 0) view = line;
  ASSERT_FALSE(view.empty()) << r.out;
  const std::string summary = view.substr(view.find_first_not_of(' ', 6));
  EXPECT_LE(summary.size(), 80u) << summary;
  EXPECT_EQ(view.find("Keys"), std::string::npos) << view;
  const test::CliResult own = test::run_cli("view --help", "outputs_help");
  EXPECT_EQ(own.exit_code, 0) << own.err;
  EXPECT_NE(own.out.find("Keys: "), std::string::npos) << own.out;
}

// A mesh the scene names relative to itself, missing: the error says the
// name as written and the absolute path it resolved to.
TEST_F(CliOutputs, AMissingMeshIsNamedAsWrittenAndAsResolved) {
  fs::create_directories(dir_ / "scenes");
  std::ofstream(dir_ / "scenes" / "s.json")
      << R"({"camera":{"eye":[0,2.5,5],"target":[0,0.7,0],"up":[0,1,0],"fovy_deg":50,"near":0.1,"far":100,
    "width":64,"height":48},"lights":[{"position":[2,5,1.5]}],"objects":[{"mesh":"../meshes/missing.off"}]})";
  // Run from the scene's parent, the scene named relative to it.
  const test::CliResult r = test::run_cli("classify scenes/s.json", "outputs_mesh", "cd '" + dir_.string() + "' &&");
  EXPECT_EQ(r.exit_code, 2);
  const std::string resolved = (dir_ / "meshes" / "missing.off").string();
  EXPECT_EQ(r.err,
            "nearcap: error (io): scenes/s.json: objects[0] (occluder): mesh '../meshes/missing.off' "
            "(resolved to " +
                resolved + "): cannot open the mesh file (no such file)\n");
}

// render --compare --table: one row per method with the record's figures.
TEST(RenderCommand, CompareTableHasARowPerMethod) {
  const std::string base = "render data/scenes/case_d.json --light 0 --compare --method zpass,zfail,policy";
  const test::CliResult json = test::run_cli(base, "outputs_render");
  if (json.exit_code == 2 && json.err.find("error (gl)") != std::string::npos)
    GTEST_SKIP() << "no headless OpenGL here: " << json.err;
  ASSERT_EQ(json.exit_code, 0) << json.err;
  const test::CliResult table = test::run_cli(base + " --table", "outputs_render");
  ASSERT_EQ(table.exit_code, 0) << table.err;
  EXPECT_FALSE(nlohmann::json::accept(table.out)) << "a table, not JSON";
  EXPECT_NE(table.out.find("gl!=emul"), std::string::npos) << table.out;
  const nlohmann::json j = nlohmann::json::parse(json.out);
  for (const nlohmann::json& m : j.at("methods")) {
    // The row: the method, then its counts in the record's order, columns
    // apart by one space or more.
    const std::string row = m.at("method").get<std::string>() + " " +
                            std::to_string(m.at("gl_vs_emulation").get<std::size_t>()) + " " +
                            std::to_string(m.at("objects_differ").get<std::size_t>()) + " " +
                            std::to_string(m.at("near_cap_differ").get<std::size_t>()) + " " +
                            std::to_string(m.at("gl_vs_exact").get<std::size_t>()) + " " +
                            std::to_string(m.at("cracks").get<std::size_t>()) + " " +
                            std::to_string(m.at("emulation_vs_exact").get<std::size_t>()) + " ";
    bool found = false;
    std::istringstream lines_of(table.out);
    for (std::string line; std::getline(lines_of, line);) {
      std::string collapsed;
      for (char c : line)
        if (c != ' ' || collapsed.empty() || collapsed.back() != ' ') collapsed += c;
      found = found || collapsed.rfind(row, 0) == 0;
    }
    EXPECT_TRUE(found) << row << "\n" << table.out;
  }
  EXPECT_NE(table.out.find("\n  object "), std::string::npos) << "the policy's occluders\n" << table.out;
  const test::CliResult lit = test::run_cli("render data/scenes/case_d.json --table --out /tmp/x", "outputs_render");
  EXPECT_EQ(lit.exit_code, 2);
  EXPECT_NE(lit.err.find("--table goes with --compare"), std::string::npos) << lit.err;
}

}  // namespace
}  // namespace nearcap
