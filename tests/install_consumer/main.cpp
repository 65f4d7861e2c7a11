// A program outside nearcap's tree, built against an installed nearcap
// (find_package(nearcap)): loads a scene and prints its silhouette edge count.
#include <cstdio>

#include "nearcap/exact/classification.hpp"
#include "nearcap/io/scene_file.hpp"

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  const nearcap::Scene scene = nearcap::load_scene(argv[1]);
  const nearcap::CameraSpaceScene exact(scene);
  std::printf("%zu silhouette edges\n", nearcap::classify_scene(exact).lights[0].objects[0].edges.size());
  return 0;
}
