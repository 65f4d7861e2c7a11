// The front door's calls (nearcap.hpp): each composes the layers' calls as
// the `nearcap` commands do (src/cli/cap_command.cpp, reference_command.cpp,
// cracks_command.cpp), so that a frame judged here is the one `nearcap cracks`
// judges with the same options.
#include "nearcap/nearcap.hpp"

#include <string>

#include "nearcap/exact/camera_space.hpp"
#include "nearcap/judge/crack_distances.hpp"

namespace nearcap {
namespace {

void check_light(const Scene& scene, std::size_t light) {
  if (light >= scene.lights.size())
    throw Error(ErrorKind::Usage, scene.source + ": light " + std::to_string(light) +
                                      " is out of range (the scene has " + std::to_string(scene.lights.size()) +
                                      " light(s))");
}

// The scene with the frame's image size: a copy whose camera has the other
// pixel grid (the meshes are shared, not copied).
Scene sized_scene(const Scene& scene, const FrameSettings& settings) {
  check_light(scene, settings.light);
  Scene sized = scene;
  if (settings.width > 0) sized.camera.width = settings.width;
  if (settings.height > 0) sized.camera.height = settings.height;
  return sized;
}

// The reference and the crack-distance measurer that frames are judged with.
struct Judge {
  explicit Judge(const Scene& scene, std::size_t light)
      : exact(scene), tracer(exact, light), reference(compute_pixel_reference(tracer)), distances(tracer, reference) {}
  JudgedFrame judged(ShadowFrame&& frame) {
    JudgedFrame j{std::move(frame), {}};
    j.report = judge_frame(j.frame, reference);
    distances.measure(j.report);
    return j;
  }
  const CameraSpaceScene exact;
  const PixelReferenceTracer tracer;
  const PixelReference reference;
  CrackDistances distances;
};

}  // namespace

NearCap exact_near_cap(const Scene& scene, std::size_t light) {
  check_light(scene, light);
  return NearCap::build(CameraSpaceScene(scene), light);
}

PixelReference exact_reference(const Scene& scene, std::size_t light) {
  check_light(scene, light);
  return compute_pixel_reference(CameraSpaceScene(scene), light);
}

gl::EmulationSettings emulation_settings(const FrameSettings& settings) {
  if (settings.width < 0 || settings.height < 0)
    throw Error(ErrorKind::Usage, "FrameSettings: the image size " + std::to_string(settings.width) + "x" +
                                      std::to_string(settings.height) + " is negative (0 keeps the camera's)");
  gl::EmulationSettings s;
  s.depth = settings.depth;
  s.depth_mapping = settings.depth_mapping;
  s.light_frustum.projection = settings.light_projection;
  return s;
}

JudgedFrame judged_frame(const Scene& scene, const FrameSettings& settings) {
  return std::move(judged_frames(scene, {settings.method}, settings).front());
}

std::vector<JudgedFrame> judged_frames(const Scene& scene, const std::vector<ShadowMethod>& methods,
                                       const FrameSettings& settings) {
  const gl::EmulationSettings emulation = emulation_settings(settings);
  const Scene sized = sized_scene(scene, settings);
  Judge judge(sized, settings.light);
  gl::ShadowFrameBatch batch(sized, settings.light, emulation);
  std::vector<JudgedFrame> frames;
  frames.reserve(methods.size());
  for (ShadowMethod m : methods) frames.push_back(judge.judged(batch.render(m)));
  return frames;
}

PolicyDecision decide_policy(const SwitchPolicy& policy, const Scene& scene, const FrameSettings& settings) {
  const gl::EmulationSettings emulation = emulation_settings(settings);
  const Scene sized = sized_scene(scene, settings);
  return analysis::decide(policy, CameraSpaceScene(sized), settings.light, emulation);
}

JudgedFrame judged_policy_frame(const SwitchPolicy& policy, const Scene& scene, const FrameSettings& settings) {
  const gl::EmulationSettings emulation = emulation_settings(settings);
  const Scene sized = sized_scene(scene, settings);
  Judge judge(sized, settings.light);
  const PolicyDecision d = analysis::decide(policy, judge.exact, settings.light, emulation);
  gl::ShadowFrameBatch batch(sized, settings.light, d.settings);
  JudgedFrame j = judge.judged(batch.render(d.object_methods));
  j.report.method = "policy";
  return j;
}

}  // namespace nearcap
