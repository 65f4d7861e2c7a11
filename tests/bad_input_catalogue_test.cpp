// The bad-input catalogue, data-driven: every entry of data/bad/catalogue.json
// names a file and the error it must produce (kind and a message fragment).
// Checked twice: through the library (the thrown Error's kind) and through the
// program (exit code 2, the message on stderr, nothing on stdout, no output
// file written).
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cctype>
#include <filesystem>
#include <set>

#include "cli_support.hpp"
#include "nearcap/error.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/scene/scene.hpp"

namespace nearcap {
namespace {

struct CatalogueEntry {
  std::string file, kind, message;
};

std::vector<CatalogueEntry> catalogue() {
  const auto text = test::slurp(std::string(NEARCAP_SOURCE_DIR) + "/data/bad/catalogue.json");
  std::vector<CatalogueEntry> entries;
  for (const auto& e : nlohmann::json::parse(text))
    entries.push_back(
        {e.at("file").get<std::string>(), e.at("kind").get<std::string>(), e.at("message").get<std::string>()});
  return entries;
}

// Test names and messages show the file, not the struct's bytes.
void PrintTo(const CatalogueEntry& e, std::ostream* os) { *os << e.file; }

class BadInput : public ::testing::TestWithParam<CatalogueEntry> {};

TEST_P(BadInput, LibraryThrowsTheCataloguedKind) {
  const CatalogueEntry& e = GetParam();
  try {
    load_scene(std::string(NEARCAP_SOURCE_DIR) + "/data/bad/" + e.file);
    FAIL() << e.file << " was accepted";
  } catch (const Error& error) {
    EXPECT_EQ(std::string(to_string(error.kind())), e.kind) << error.what();
    EXPECT_NE(std::string(error.what()).find(e.message), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find(e.file), std::string::npos) << "the message names the file";
  }
}

TEST_P(BadInput, ProgramExitsWithTwoAndWritesNothing) {
  const CatalogueEntry& e = GetParam();
  const std::string scene = "data/bad/" + e.file;
  const auto out_dir = test::temp_path("nearcap_bad_" + e.file);
  std::filesystem::remove_all(out_dir);
  const std::string tag = "bad";
  for (const std::string& args :
       {"classify " + scene, "classify --json " + scene, "cap " + scene + " --light 0 --out " + out_dir.string(),
        "reference " + scene + " --light 0 --out " + out_dir.string()}) {
    const test::CliResult r = test::run_cli(args, tag);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
    EXPECT_NE(r.err.find("error (" + e.kind + ")"), std::string::npos) << args << "\n" << r.err;
    EXPECT_NE(r.err.find(e.message), std::string::npos) << args << "\n" << r.err;
    EXPECT_TRUE(r.out.empty()) << args << "\n" << r.out;
    EXPECT_FALSE(std::filesystem::exists(out_dir)) << args;
  }
}

INSTANTIATE_TEST_SUITE_P(Catalogue, BadInput, ::testing::ValuesIn(catalogue()),
                         [](const ::testing::TestParamInfo<CatalogueEntry>& param_info) {
                           std::string name;
                           for (char c : param_info.param.file)
                             name += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
                           return name;
                         });

TEST(BadInputCatalogue, CoversTheIssueList) {
  // The kinds of fault the hardening issue lists must each have an entry.
  std::set<std::string> files;
  for (const CatalogueEntry& e : catalogue()) files.insert(e.file);
  for (const char* f :
       {"scene_open_mesh_off.json", "scene_nonmanifold_edge_off.json", "scene_inconsistent_orientation_off.json",
        "scene_inward_off.json", "scene_nan_coordinate_off.json", "scene_inf_coordinate_off.json",
        "scene_empty_off.json", "light_inside.json", "light_on_surface.json", "zero_size_frustum.json",
        "inverted_frustum.json", "near_ge_far.json", "singular_view.json", "zero_viewport.json", "missing_mesh.json",
        "truncated.json", "scene_truncated_off.json", "unknown_key.json", "wrong_type.json", "huge_coordinates.json",
        // the reliability report
        "eye_beyond_range.json", "near_denormal.json", "width_fraction.json", "duplicate_key.json",
        "mesh_no_extension.json", "mesh_dev_zero.json", "mesh_directory.json"})
    EXPECT_TRUE(files.count(f)) << f;
}

}  // namespace
}  // namespace nearcap
