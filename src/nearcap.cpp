// The front door's calls (nearcap.hpp): each composes the layers' calls as
// the `nearcap` commands do (src/cli/cap_command.cpp, reference_command.cpp,
// cracks_command.cpp), so that a frame judged here is the one `nearcap cracks`
// judges with the same options.
#include "nearcap/nearcap.hpp"

#include <new>
#include <stdexcept>
#include <string>
#include <utility>

#include "nearcap/exact/camera_space.hpp"
#include "nearcap/io/scene_builder.hpp"
#include "nearcap/judge/crack_distances.hpp"
#include "nearcap/named_values.hpp"

namespace nearcap {
namespace {

// The scene's fields as load_scene leaves them (check_scene_fields), and the light.
void check_light(const Scene& scene, std::size_t light) {
  check_scene_fields(scene);
  if (light >= scene.lights.size())
    throw Error(ErrorKind::Usage, scene_name(scene) + ": light " + std::to_string(light) +
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

// `task()`, with memory that runs out as the command line reports it:
// Error(Resource) (a frame of the largest viewport needs gigabytes).
// `pixels`: whether the task's memory grows with the camera's pixels.
template <class Task>
auto within_memory(const Scene& scene, bool pixels, Task&& task) {
  const auto out_of_memory = [&] {
    return Error(ErrorKind::Resource, scene_name(scene) + ": out of memory" +
                                          (pixels ? " (" + std::to_string(scene.camera.width) + "x" +
                                                        std::to_string(scene.camera.height) + " pixels)"
                                                  : std::string()));
  };
  try {
    return task();
  } catch (const std::bad_alloc&) {
    throw out_of_memory();
  } catch (const std::length_error&) {
    throw out_of_memory();
  }
}

template <class E>
void check_named(E value, const char* field) {
  if (name_of(value) == "?")
    throw Error(ErrorKind::Usage, std::string("FrameSettings: ") + field + " " +
                                      std::to_string(static_cast<long long>(value)) + " is not one of " +
                                      names_joined<E>());
}

}  // namespace

NearCap exact_near_cap(const Scene& scene, std::size_t light) {
  check_light(scene, light);
  return within_memory(scene, false, [&] { return NearCap::build(CameraSpaceScene(scene), light); });
}

PixelReference exact_reference(const Scene& scene, std::size_t light) {
  check_light(scene, light);
  return within_memory(scene, true, [&] { return compute_pixel_reference(CameraSpaceScene(scene), light); });
}

gl::EmulationSettings emulation_settings(const FrameSettings& settings) {
  if (settings.width < 0 || settings.height < 0 || settings.width > 16384 || settings.height > 16384)
    throw Error(ErrorKind::Usage, "FrameSettings: the image size " + std::to_string(settings.width) + "x" +
                                      std::to_string(settings.height) +
                                      " is outside [1, 16384] pixels (0 keeps the camera's)");
  check_named(settings.depth, "depth");
  check_named(settings.depth_mapping, "depth_mapping");
  check_named(settings.light_projection, "light_projection");
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
  for (ShadowMethod m : methods) check_named(m, "method");
  const Scene sized = sized_scene(scene, settings);
  return within_memory(sized, true, [&] {
    Judge judge(sized, settings.light);
    gl::ShadowFrameBatch batch(sized, settings.light, emulation);
    std::vector<JudgedFrame> frames;
    frames.reserve(methods.size());
    for (ShadowMethod m : methods) frames.push_back(judge.judged(batch.render(m)));
    return frames;
  });
}

PolicyDecision decide_policy(const SwitchPolicy& policy, const Scene& scene, const FrameSettings& settings) {
  const gl::EmulationSettings emulation = emulation_settings(settings);
  const Scene sized = sized_scene(scene, settings);
  return within_memory(sized, false,
                       [&] { return analysis::decide(policy, CameraSpaceScene(sized), settings.light, emulation); });
}

JudgedFrame judged_policy_frame(const SwitchPolicy& policy, const Scene& scene, const FrameSettings& settings) {
  const gl::EmulationSettings emulation = emulation_settings(settings);
  const Scene sized = sized_scene(scene, settings);
  return within_memory(sized, true, [&] {
    Judge judge(sized, settings.light);
    const PolicyDecision d = analysis::decide(policy, judge.exact, settings.light, emulation);
    gl::ShadowFrameBatch batch(sized, settings.light, d.settings);
    JudgedFrame j = judge.judged(batch.render(d.object_methods));
    j.report.method = "policy";
    return j;
  });
}

}  // namespace nearcap
