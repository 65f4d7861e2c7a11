// A box over a large receiver, a light, and a look-at camera where a test
// puts them: the scene the engine-policy and switch-policy tests build.
#pragma once

#include <string>

#include "nearcap/io/mesh_file.hpp"
#include "nearcap/io/scene_builder.hpp"
#include "nearcap/scene/scene.hpp"

namespace nearcap::test {

inline Affine3d translate(double x, double y, double z) {
  Affine3d a;
  a.rows[0][3] = x;
  a.rows[1][3] = y;
  a.rows[2][3] = z;
  return a;
}

struct BoxSceneOptions {
  double near = 0.05;
  Vec3d target{0, 0, 0};
  Vec3d centre{0, 0, 0};  // the box's centre
  double size = 1.0;      // the box's edge (data/meshes/box.off is the unit box)
  int width = 64, height = 48;
  std::string occluder = "box.off";  // in data/meshes/: another mesh in the box's place
};

// The box (an occluder) and a 40-wide receiver below it (top face at y = -0.6).
inline Scene box_scene(const Vec3d& eye, const Vec3d& light, const BoxSceneOptions& o = {}) {
  const TriangleMesh box_mesh = read_mesh(std::string(NEARCAP_SOURCE_DIR) + "/data/meshes/box.off");
  SceneBuilder b("box scene");
  b.camera(look_at_camera(eye, o.target, {0, 1, 0}, 60, o.near, 100, o.width, o.height));
  b.light(light);
  Affine3d box = translate(o.centre.x, o.centre.y, o.centre.z);
  for (int k = 0; k < 3; ++k) box.rows[k][k] = o.size;
  b.object(
      o.occluder == "box.off" ? box_mesh : read_mesh(std::string(NEARCAP_SOURCE_DIR) + "/data/meshes/" + o.occluder),
      box);
  Affine3d ground = translate(0, -20.6, 0);
  for (int k = 0; k < 3; ++k) ground.rows[k][k] = 40;
  b.receiver(box_mesh, ground);
  return b.build();
}

// AtomicZP's hard case: the unit box under a light at (0, 5, 0), the eye
// below the box at height -0.1 and x = `x`, next to the side plane through
// the light and the top edge x = 0.5 (at x = kSidePlaneX), on a 32x24 frame.
constexpr double kSidePlaneX = 0.5 * 5.1 / 4.5;
inline Scene eye_near_side_plane(double x) {
  BoxSceneOptions o;
  o.width = 32;
  o.height = 24;
  o.target = {x + 1, -0.3, 1};
  return box_scene({x, -0.1, 0}, {0, 5, 0}, o);
}

// A box of edge 4 straight ahead whose front face lies exactly in the near
// plane (z = -0.5 in camera space: the view is the identity) and fills the
// frame, lit from in front by a light at (3, 4, 1).  GL's clip volume is
// closed at the near plane (-w <= z), so the face is drawn and seen lit.
inline Scene near_plane_face() {
  BoxSceneOptions o;
  o.near = 0.5;
  o.target = {0, 0, -1};
  o.centre = {0, 0, -2.5};
  o.size = 4;
  return box_scene({0, 0, 0}, {3, 4, 1}, o);
}

// Two boxes under a light at (0, 8, 0): `a` above and beside the eye, its
// volume cut by the near plane (a near-cap), `b` straight above the eye (the
// eye in its volume: an eye count of 1).  `a_occluder`, `b_occluder` say
// which are occluders (the other is a receiver: drawn in the depth pre-pass
// as before, casting no volume).
inline Scene two_boxes(bool a_occluder, bool b_occluder) {
  const TriangleMesh box = read_mesh(std::string(NEARCAP_SOURCE_DIR) + "/data/meshes/box.off");
  SceneBuilder b("two boxes");
  b.camera(look_at_camera({0, 0, 0}, {3, -0.5, 2}, {0, 1, 0}, 60, 0.05, 100, 96, 72));
  b.light({0, 8, 0});
  const Affine3d a_at = translate(0.52, 3.5, 0.2), b_at = translate(0, 2, 0);
  if (a_occluder)
    b.object(box, a_at);
  else
    b.receiver(box, a_at);
  if (b_occluder)
    b.object(box, b_at);
  else
    b.receiver(box, b_at);
  Affine3d ground = translate(0, -20.6, 0);
  for (int k = 0; k < 3; ++k) ground.rows[k][k] = 40;
  b.receiver(box, ground);
  return b.build();
}

}  // namespace nearcap::test
