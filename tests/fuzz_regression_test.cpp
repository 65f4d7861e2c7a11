// Every input that ever crashed a fuzzer lives in fuzz/regressions/: replayed
// through the same reader as its fuzzer, it must be accepted or rejected with a
// nearcap::Error, nothing else.
#include <gtest/gtest.h>

#include <filesystem>

#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "nearcap/analysis/policy_fit.hpp"
#include "nearcap/analysis/switch_policy.hpp"
#include "nearcap/error.hpp"
#include "nearcap/io/mesh_file.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/scene/mesh.hpp"
#include "nearcap/scene/scene.hpp"

namespace nearcap {
namespace {

namespace fs = std::filesystem;

TEST(FuzzRegressions, SceneInputsFailCleanly) {
  const fs::path dir = fs::path(NEARCAP_SOURCE_DIR) / "fuzz" / "regressions" / "scene";
  int replayed = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string text = test::slurp(entry.path());
    try {
      (void)parse_scene(text, entry.path().string(), (fs::path(NEARCAP_SOURCE_DIR) / "fuzz" / "meshes").string());
    } catch (const Error&) {
    } catch (const std::exception& e) {
      ADD_FAILURE() << entry.path() << ": escaped as " << e.what();
    } catch (...) {
      ADD_FAILURE() << entry.path() << ": escaped as a non-standard exception";
    }
    ++replayed;
  }
  EXPECT_GT(replayed, 0);
}

TEST(FuzzRegressions, MeshInputsFailCleanly) {
  const fs::path root = fs::path(NEARCAP_SOURCE_DIR) / "fuzz" / "regressions";
  for (const char* format : {"off", "obj", "ply", "stl"}) {
    const fs::path dir = root / format;
    if (!fs::exists(dir)) continue;
    for (const auto& entry : fs::directory_iterator(dir)) {
      try {
        TriangleMesh mesh = parse_mesh(test::slurp(entry.path()), format, entry.path().string());
        validate_occluder(mesh);
      } catch (const Error&) {
      } catch (const std::exception& e) {
        ADD_FAILURE() << entry.path() << ": escaped as " << e.what();
      } catch (...) {
        ADD_FAILURE() << entry.path() << ": escaped as a non-standard exception";
      }
    }
  }
}

// Every crash input has the error it must produce now (fuzz/regressions/expected.json),
// and every file in fuzz/regressions/ is listed there.
TEST(FuzzRegressions, EachCrashInputGivesItsDocumentedError) {
  const fs::path root = fs::path(NEARCAP_SOURCE_DIR) / "fuzz" / "regressions";
  const nlohmann::json expected = nlohmann::json::parse(test::slurp(root / "expected.json"));
  std::size_t files = 0;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    if (!entry.is_regular_file() || entry.path().filename() == "expected.json") continue;
    ++files;
    const std::string key = fs::relative(entry.path(), root).generic_string();
    ASSERT_TRUE(expected.contains(key)) << key << " has no expected error in expected.json";
    const std::string format = entry.path().parent_path().filename().string();
    try {
      if (format == "scene") {
        (void)parse_scene(test::slurp(entry.path()), entry.path().string(),
                          (fs::path(NEARCAP_SOURCE_DIR) / "fuzz" / "meshes").string());
      } else if (format == "policy") {
        (void)analysis::parse_policy(test::slurp(entry.path()), entry.path().string());
      } else if (format == "csv") {
        (void)analysis::policy_samples_from_text(test::slurp(entry.path()), entry.path().string(),
                                                 gl::ShadowMethod::ZPPlusCorrected, gl::ShadowMethod::ZFail);
        (void)analysis::cost_samples_from_text(test::slurp(entry.path()), entry.path().string(),
                                               gl::ShadowMethod::ZFail);
      } else {
        TriangleMesh mesh = parse_mesh(test::slurp(entry.path()), format, entry.path().string());
        validate_occluder(mesh);
      }
      ADD_FAILURE() << key << " was accepted";
    } catch (const Error& e) {
      EXPECT_EQ(std::string(to_string(e.kind())), expected[key].at("kind").get<std::string>()) << key;
      EXPECT_NE(std::string(e.what()).find(expected[key].at("message").get<std::string>()), std::string::npos)
          << key << ": " << e.what();
    }
  }
  EXPECT_EQ(files, expected.size());
}

TEST(FuzzSeeds, PolicyAndCsvSeedsAreRead) {
  // fuzz_policy and fuzz_csv start from real files: the shipped policies'
  // kind and rows of a small sweep, each read as the fuzzer reads it.
  const fs::path root = fs::path(NEARCAP_SOURCE_DIR) / "fuzz" / "seeds";
  int policies = 0, csvs = 0;
  for (const auto& entry : fs::directory_iterator(root / "policy")) {
    EXPECT_NO_THROW((void)analysis::parse_policy(test::slurp(entry.path()), entry.path().string())) << entry.path();
    ++policies;
  }
  for (const auto& entry : fs::directory_iterator(root / "csv")) {
    EXPECT_NO_THROW((void)analysis::cost_samples_from_text(test::slurp(entry.path()), entry.path().string(),
                                                           gl::ShadowMethod::ZFail))
        << entry.path();
    ++csvs;
  }
  EXPECT_GE(policies, 3);
  EXPECT_GE(csvs, 2);
}

TEST(FuzzSeeds, SceneSeedsAreValidScenes) {
  // The seeds start the fuzzer from the inside of the format: each must be
  // accepted by the reader exactly as the fuzzer calls it (meshes from fuzz/meshes).
  const fs::path dir = fs::path(NEARCAP_SOURCE_DIR) / "fuzz" / "seeds" / "scene";
  int seeds = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    EXPECT_NO_THROW((void)parse_scene(test::slurp(entry.path()), entry.path().string(),
                                      (fs::path(NEARCAP_SOURCE_DIR) / "fuzz" / "meshes").string()))
        << entry.path();
    ++seeds;
  }
  EXPECT_GT(seeds, 0);
}

TEST(FuzzSeeds, MeshSeedsAreValidOccludersInEveryFormatVariant) {
  // Each mesh fuzzer starts from small valid files of its format (ascii and
  // binary PLY and STL; OBJ with every face-entry form): each must read and
  // validate exactly as the fuzzer calls it.
  const fs::path root = fs::path(NEARCAP_SOURCE_DIR) / "fuzz" / "seeds";
  for (const char* format : {"obj", "ply", "stl"}) {
    int seeds = 0;
    for (const auto& entry : fs::directory_iterator(root / format)) {
      try {
        TriangleMesh mesh = parse_mesh(test::slurp(entry.path()), format, entry.path().string());
        validate_occluder(mesh);
        EXPECT_GE(mesh.triangle_count(), 4u) << entry.path();
      } catch (const Error& e) {
        ADD_FAILURE() << entry.path() << ": " << e.what();
      }
      ++seeds;
    }
    EXPECT_GE(seeds, 2) << format;
  }
}

}  // namespace
}  // namespace nearcap
