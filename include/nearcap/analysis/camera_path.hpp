// nearcap/analysis/camera_path.hpp — camera paths: keyframes over a scene,
// interpolated to N frames (docs/sweeps-and-report.md, "Camera paths").
//
// A path file (data/paths/*.json) names a base scene (lights, objects, and the
// camera's far plane and viewport) and a list of look-at keyframes spread
// evenly over `frames` frames:
//   {"description": "...", "scene": "../scenes/room.json", "frames": 60,
//    "width": 160, "height": 120,          (optional: the base scene's otherwise)
//    "keyframes": [{"eye": [x,y,z], "target": [x,y,z], "up": [0,1,0],
//                   "fovy_deg": 60, "near": 0.1}, ...]}
// Between two keyframes eye, target and up are interpolated linearly, fovy_deg
// linearly and near geometrically (so a path can sweep near planes over
// orders of magnitude); a keyframe without up, fovy_deg or near takes the
// previous keyframe's, and the first takes the base scene's (which must then
// use the look-at camera form).  Each frame is a scene file's text (mesh
// paths absolute), so any frame of a sweep can be written out and replayed
// alone with `nearcap cracks`.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "nearcap/numeric/vec3.hpp"

namespace nearcap {
class MeshCache;  // io/scene_file.hpp
}  // namespace nearcap

namespace nearcap::analysis {

struct CameraKeyframe {
  Vec3d eye, target;
  Vec3d up{0, 1, 0};
  double fovy_deg = 60, near = 0.1;
};

struct CameraPath {
  std::string source;  // the path file, for messages
  std::string description;
  std::string scene_file;  // the base scene (resolved path)
  int frames = 0;
  std::vector<CameraKeyframe> keyframes;  // at least one; missing fields filled in
  double far = 100;
  int width = 0, height = 0;
  std::string base_scene_json;  // the base scene's text with absolute mesh paths, camera removed
};

// Reads and checks a path file (Error naming the file and the field); reads
// the base scene too, and checks that it loads (its meshes from `meshes` when
// given: a sweep's cache, so that the frames find them read).
CameraPath load_camera_path(const std::string& path, MeshCache* meshes = nullptr);

// The keyframe values at frame `frame` (0 <= frame < frames).
CameraKeyframe path_camera(const CameraPath& path, int frame);

// Frame `frame` as a scene file's text.
std::string path_frame_json(const CameraPath& path, int frame);

}  // namespace nearcap::analysis
