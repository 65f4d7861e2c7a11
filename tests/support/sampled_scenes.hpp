// tests/support/sampled_scenes.hpp — the hard-case sampler's configurations
// (analysis/hard_case_sampler.hpp) as the tests walk them: a spec over the
// bundled meshes, and one loop that parses each sample into a scene and skips
// the ones the scene reader rejects.
//
// The sampler does not avoid every invalid scene (it can put a light inside
// an occluder, or a vertex out of range), and the scene reader rejects such a
// file with an Error: that sample is not a configuration, so a test skips it
// and may count the rejections by kind.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "nearcap/analysis/hard_case_sampler.hpp"
#include "nearcap/error.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/scene/scene.hpp"

namespace nearcap::test {

// The sampler's spec with `seed` and the bundled meshes (data/meshes); every
// other field at SamplerSpec's default (every kind, 48 x 36 pixels, no bunny).
inline analysis::SamplerSpec bundled_sampler_spec(std::uint64_t seed) {
  analysis::SamplerSpec spec;
  spec.seed = seed;
  spec.mesh_directory = std::string(NEARCAP_SOURCE_DIR) + "/data/meshes";
  return spec;
}

// Sample `index` of `sampler` parsed as a scene named "sample INDEX" (mesh
// paths in the sample are absolute); nothing when the reader rejects it, and
// then `rejection` (when given) receives the error's kind.
inline std::optional<Scene> sampled_scene(const analysis::HardCase& sample, ErrorKind* rejection = nullptr) {
  try {
    return parse_scene(sample.scene_json, "sample " + std::to_string(sample.index), ".");
  } catch (const Error& e) {
    if (rejection) *rejection = e.kind();
    return std::nullopt;
  }
}

// What a walk over the samples met.
struct SampleWalk {
  std::size_t scenes = 0;                       // samples visited
  std::map<std::string, std::size_t> rejected;  // samples the reader rejected, by error kind (to_string)
};

// Calls visit(scene, sample) for each index of `indices` in order whose
// sample the reader accepts (sampled_scene).  The walk stops after a visit
// that records a fatal failure (an ASSERT_ in it), as a loop in the test's
// body would.
template <class Visit>
SampleWalk for_each_sampled_scene(const analysis::HardCaseSampler& sampler, const std::vector<std::uint64_t>& indices,
                                  Visit&& visit) {
  SampleWalk walk;
  for (std::uint64_t index : indices) {
    const analysis::HardCase sample = sampler.sample(index);
    ErrorKind rejection{};
    const std::optional<Scene> scene = sampled_scene(sample, &rejection);
    if (!scene) {
      ++walk.rejected[std::string(to_string(rejection))];
      continue;
    }
    ++walk.scenes;
    visit(*scene, sample);
    if (::testing::Test::HasFatalFailure()) break;
  }
  return walk;
}

// The same over the samples 0 .. count - 1.
template <class Visit>
SampleWalk for_each_sampled_scene(const analysis::HardCaseSampler& sampler, std::uint64_t count, Visit&& visit) {
  std::vector<std::uint64_t> indices(count);
  for (std::uint64_t k = 0; k < count; ++k) indices[k] = k;
  return for_each_sampled_scene(sampler, indices, std::forward<Visit>(visit));
}

}  // namespace nearcap::test
