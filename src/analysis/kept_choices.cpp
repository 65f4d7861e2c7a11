// A frame loop's kept choices (see kept_choices.hpp).
#include "nearcap/analysis/kept_choices.hpp"

#include <algorithm>

namespace nearcap::analysis {
namespace {

// Candidates on every frame, admitted by no per-frame test.
bool keepable(gl::ShadowMethod method, gl::LightProjection projection) {
  return method == gl::ShadowMethod::ZFail ||
         (method == gl::ShadowMethod::ZPPlus && projection == gl::LightProjection::ClippedSides);
}

}  // namespace

bool KeptChoices::same_frame_setup(const Entry& e, const SwitchPolicy& policy, const Scene& scene, std::size_t light,
                                   gl::NearPlane near_plane, bool depth_limited) const {
  if (e.policy != &policy || e.light != light || light >= scene.lights.size() ||
      !(e.light_position.x == scene.lights[light].position.x && e.light_position.y == scene.lights[light].position.y &&
        e.light_position.z == scene.lights[light].position.z) ||
      e.objects.size() != scene.objects.size() || e.width != scene.camera.width || e.height != scene.camera.height ||
      e.near_plane != near_plane || e.depth_limited != depth_limited)
    return false;
  for (std::size_t o = 0; o < scene.objects.size(); ++o) {
    const SceneObject& so = scene.objects[o];
    const ObjectKey& k = e.objects[o];
    if (k.mesh != so.mesh || k.occluder != so.occluder || k.object_to_world.rows != so.object_to_world.rows)
      return false;
  }
  return true;
}

std::optional<KeptChoices::Choice> KeptChoices::take(const SwitchPolicy& policy, const Scene& scene, std::size_t light,
                                                     gl::NearPlane near_plane, bool depth_limited) {
  const auto it = std::find_if(entries_.begin(), entries_.end(), [&](const Entry& e) { return e.light == light; });
  if (it == entries_.end()) return std::nullopt;
  if (it->choice.frames_since_priced >= kMaxKeptFrames ||
      !same_frame_setup(*it, policy, scene, light, near_plane, depth_limited)) {
    entries_.erase(it);
    return std::nullopt;
  }
  ++it->choice.frames_since_priced;
  ++frames_kept_;
  return it->choice;
}

void KeptChoices::remember(const SwitchPolicy& policy, const Scene& scene, std::size_t light, gl::NearPlane near_plane,
                           bool depth_limited, const std::vector<gl::ShadowMethod>& object_methods,
                           gl::LightProjection projection, double margin) {
  entries_.erase(std::remove_if(entries_.begin(), entries_.end(), [&](const Entry& e) { return e.light == light; }),
                 entries_.end());
  if (!(margin >= kMargin) || light >= scene.lights.size() || object_methods.size() != scene.objects.size()) return;
  for (std::size_t o = 0; o < scene.objects.size(); ++o)
    if (scene.objects[o].occluder && !keepable(object_methods[o], projection)) return;
  Entry e;
  e.policy = &policy;
  e.light = light;
  e.light_position = scene.lights[light].position;
  e.objects.reserve(scene.objects.size());
  for (const SceneObject& so : scene.objects) e.objects.push_back({so.mesh, so.object_to_world, so.occluder});
  e.width = scene.camera.width;
  e.height = scene.camera.height;
  e.near_plane = near_plane;
  e.depth_limited = depth_limited;
  e.choice = {object_methods, projection, 0};
  entries_.push_back(std::move(e));
}

}  // namespace nearcap::analysis
