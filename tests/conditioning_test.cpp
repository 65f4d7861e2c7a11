// Conditioning features (analysis/conditioning.hpp) and the singular values
// they rest on (numeric/singular_values.hpp).
#include <gtest/gtest.h>

#include <cmath>

#include "nearcap/analysis/camera_path.hpp"
#include "nearcap/analysis/conditioning.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/numeric/singular_values.hpp"

namespace nearcap {
namespace {

using Matrix = std::array<std::array<double, 4>, 4>;

TEST(SingularValues, KnownMatrices) {
  const Matrix diagonal{{{1, 0, 0, 0}, {0, -4, 0, 0}, {0, 0, 2, 0}, {0, 0, 0, 0.5}}};
  const auto s = singular_values(diagonal);
  EXPECT_DOUBLE_EQ(s[0], 4);
  EXPECT_DOUBLE_EQ(s[3], 0.5);
  EXPECT_DOUBLE_EQ(condition_number(diagonal), 8);
  // A rotation is perfectly conditioned.
  const double c = std::cos(0.3), sn = std::sin(0.3);
  const Matrix rotation{{{c, -sn, 0, 0}, {sn, c, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}}};
  EXPECT_NEAR(condition_number(rotation), 1.0, 1e-14);
  // The 4x4 Hilbert matrix: condition number 15513.738738929... (2-norm).
  Matrix hilbert{};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) hilbert[i][j] = 1.0 / (i + j + 1);
  // A backward-stable SVD moves sigma_min by a few eps |A|, so the condition
  // number by a few eps kappa^2 (about 5e-8 each here): 1e-6 allows twenty.
  EXPECT_NEAR(condition_number(hilbert), 15513.738738929, 1e-6);
  // Ill-conditioned: singular values 1 and 1e-12 survive (A^T A would lose the small one).
  const Matrix skewed{{{1, 1, 0, 0}, {0, 1e-12, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}}};
  // The exact value is 2e12 (1 + O(1e-24)); one-sided Jacobi keeps the small
  // singular value to a few eps relative, 1e-12 allows thousands.
  EXPECT_NEAR(condition_number(skewed) / 2e12, 1.0, 1e-12);
  const Matrix singular{{{1, 2, 0, 0}, {2, 4, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}}};
  EXPECT_TRUE(std::isinf(condition_number(singular)) || condition_number(singular) > 1e15);
}

TEST(Conditioning, TheLightsDistanceToTheNearPlaneIsExact) {
  // Camera at the origin looking down -z, near 0.5; the light at z = -0.25 in
  // camera space: (l_z + near) / near = 0.5 exactly.
  const std::string json = R"({"camera":{"eye":[0,0,0],"target":[0,0,-1],"up":[0,1,0],"fovy_deg":60,"near":0.5,
    "far":100,"width":32,"height":24},"lights":[{"position":[0.1,0.2,-0.25]}],
    "objects":[{"mesh":")" +
                           std::string(NEARCAP_SOURCE_DIR) + R"(/data/meshes/box.off","translate":[0,0,-5]}]})";
  const Scene scene = parse_scene(json, "inline", ".");
  const CameraSpaceScene cs(scene);
  const auto f = analysis::conditioning_features(cs, 0, gl::LightFrustumChoice{}, gl::Arithmetic::Separate);
  EXPECT_EQ(f.light_near_distance, 0.5);
  EXPECT_TRUE(f.light_frustum_defined);
  EXPECT_EQ(f.l_near_over_l_far, 0.5) << "min(d / d_max, 1/2): the box is far away";
  EXPECT_GT(f.cond_projection, 1.0);
}

TEST(Conditioning, TheNearPlaneSweepGetsWorseAsTheLightNearsTheNearPlane) {
  // data/paths/near_plane_sweep.json carries the near plane through the light:
  // frame 48 has the light 1.6 near distances in front of it, frame 31 (case D) 0.02.
  const analysis::CameraPath path =
      analysis::load_camera_path(std::string(NEARCAP_SOURCE_DIR) + "/data/paths/near_plane_sweep.json");
  auto features = [&](int frame) {
    const Scene scene = parse_scene(analysis::path_frame_json(path, frame), "frame", ".");
    const CameraSpaceScene cs(scene);
    return analysis::conditioning_features(cs, 0, gl::LightFrustumChoice{}, gl::Arithmetic::Separate);
  };
  const auto easy = features(48), hard = features(31);
  EXPECT_GT(std::fabs(easy.light_near_distance), 10 * std::fabs(hard.light_near_distance));
  EXPECT_GT(hard.skew, 10 * easy.skew);
  EXPECT_GT(hard.cond_light_transform, 10 * easy.cond_light_transform);
  EXPECT_GT(hard.cap_window_error_px, 5 * easy.cap_window_error_px);
  EXPECT_GT(hard.cap_window_error_ulp, 5 * easy.cap_window_error_ulp);
  EXPECT_GT(easy.cap_vertices, 0u);
  EXPECT_GT(hard.cap_vertices, 0u);
  EXPECT_LT(easy.cap_window_error_px, 0.01);
}

}  // namespace
}  // namespace nearcap
