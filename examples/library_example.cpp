// nearcap as a library, through its front door (nearcap/nearcap.hpp): a scene
// file's exact near-cap and exact reference for its first light, every
// stencil method's frame judged against that reference, and the switch
// policy's choice per occluder, judged too.
//   library_example SCENE POLICY   e.g. data/scenes/case_d.json data/policy.json
// Built and run by the test suite (LibraryExample.*, which checks that it
// prints what `nearcap cap`, `reference` and `cracks` print); the README
// shows its core.
#include <cstdio>

#include "nearcap/nearcap.hpp"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s SCENE POLICY\n", argv[0]);
    return 2;
  }
  using namespace nearcap;
  try {
    const Scene scene = load_scene(argv[1]);

    const NearCap cap = exact_near_cap(scene, 0);
    std::printf("near-cap: %zu faces, largest count %zu\n", cap.faces().size(), cap.max_count());

    const PixelReference reference = exact_reference(scene, 0);  // the ground truth, per pixel
    std::size_t shadowed = 0;
    for (int j = 0; j < reference.height; ++j)
      for (int i = 0; i < reference.width; ++i) shadowed += reference.shadowed(i, j);
    std::printf("reference: %zu pixels shadowed\n", shadowed);

    FrameSettings settings;  // light 0, the camera's pixels, a 24-bit depth buffer
    const std::vector<ShadowMethod> methods = {ShadowMethod::ZPass, ShadowMethod::ZFail, ShadowMethod::ZPPlus,
                                               ShadowMethod::ZPPlusCorrected, ShadowMethod::Preload};
    for (const JudgedFrame& f : judged_frames(scene, methods, settings))  // one reference for all five
      std::printf("%s: %zu wrong pixels of %zu seen, %zu cracks\n", f.report.method.c_str(), f.report.wrong,
                  f.report.pixels_seen, *f.report.cracks);

    const SwitchPolicy policy = load_policy(argv[2]);
    const PolicyDecision decision = decide_policy(policy, scene, settings);
    for (std::size_t o = 0; o < scene.objects.size(); ++o)
      if (scene.objects[o].occluder)
        std::printf("object %zu: %s (%s)\n", o, std::string(to_string(decision.object_methods[o])).c_str(),
                    decision.reason(o).c_str());
    const JudgedFrame p = judged_policy_frame(policy, scene, settings);
    std::printf("policy: %zu wrong pixels of %zu seen, %zu cracks\n", p.report.wrong, p.report.pixels_seen,
                *p.report.cracks);
  } catch (const Error& e) {
    std::fprintf(stderr, "library_example: error (%s): %s\n", std::string(to_string(e.kind())).c_str(), e.what());
    return 2;
  }
  return 0;
}
