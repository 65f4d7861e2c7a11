// nearcap as a library: a scene built in memory from an OpenMesh mesh, its
// silhouette cases, the exact reference, two float methods judged against it.
// Built and run by the test suite (LibraryExample.Runs); the README shows it.
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <cstdio>

#include "nearcap/exact/classification.hpp"
#include "nearcap/exact/pixel_reference.hpp"
#include "nearcap/gl/shadow_methods.hpp"
#include "nearcap/io/openmesh_adapter.hpp"
#include "nearcap/io/scene_builder.hpp"
#include "nearcap/judge/crack_map.hpp"

using TriMesh = OpenMesh::TriMesh_ArrayKernelT<>;

// A closed, outward unit cube as an application might hold it.
TriMesh cube() {
  TriMesh m;
  std::vector<TriMesh::VertexHandle> v;
  for (int i = 0; i < 8; ++i)
    v.push_back(m.add_vertex({(i & 4) ? 0.5f : -0.5f, (i & 2) ? 0.5f : -0.5f, (i & 1) ? 0.5f : -0.5f}));
  const int faces[12][3] = {{0, 1, 3}, {0, 3, 2}, {4, 6, 7}, {4, 7, 5}, {0, 4, 5}, {0, 5, 1},
                            {2, 3, 7}, {2, 7, 6}, {0, 2, 6}, {0, 6, 4}, {1, 5, 7}, {1, 7, 3}};
  for (const auto& f : faces) m.add_face(v[f[0]], v[f[1]], v[f[2]]);
  return m;
}

int main() {
  using namespace nearcap;
  // A ground quad (a receiver need not be closed), held directly as a TriangleMesh.
  TriangleMesh ground;
  ground.source = "ground";
  ground.positions = {{-10, 0, -10}, {-10, 0, 10}, {10, 0, 10}, {10, 0, -10}};
  ground.triangles = {{0, 1, 2}, {0, 2, 3}};

  Affine3d lift;  // the cube one unit above the ground
  lift.rows[1][3] = 1.0;
  // The eye under the cube, in its shadow: Z-pass is wrong on every pixel it sees.
  const Scene scene = SceneBuilder("example")
                          .camera(look_at_camera({0.1, 0.3, 0.1}, {3, 0, 3}, {0, 1, 0}, 60, 0.05, 100, 160, 120))
                          .light({0, 4, 0})
                          .object(mesh_from_openmesh(cube(), "cube"), lift)
                          .receiver(ground)
                          .build();  // validated like a scene file

  const CameraSpaceScene exact(scene);
  const SceneClassification cases = classify_scene(exact);
  const ObjectClassification& cube_cases = cases.lights[0].objects[0];
  std::printf("cube: %zu silhouette edges, %zu of case B, %zu of case D\n", cube_cases.edges.size(),
              cube_cases.case_counts[static_cast<int>(QuadCase::B)],
              cube_cases.case_counts[static_cast<int>(QuadCase::D)]);

  const PixelReference reference = compute_pixel_reference(exact, 0);  // the ground truth
  for (gl::ShadowMethod m : {gl::ShadowMethod::ZPass, gl::ShadowMethod::ZPPlusCorrected}) {
    const CrackReport r = judge_frame(gl::render_shadow_frame(scene, 0, m), reference);
    std::printf("%s: %zu wrong pixels of %zu seen\n", std::string(to_string(m)).c_str(), r.wrong, r.pixels_seen);
  }
  return 0;
}
