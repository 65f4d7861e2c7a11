// nearcap/analysis/kept_choices.hpp — a frame loop's priced choices, kept
// for the next few frames where the prices that made them were far apart.
//
// Along a camera path the lights and occluders stay put and the camera moves
// a little from one frame to the next, and so do the candidates' prices.
// Where the cost decision's choice undercut every other choice it weighed by
// a wide margin, the next frames' pricing would make it again; a frame loop
// that hands decide() a KeptChoices (switch_policy.hpp) takes it without
// pricing on up to kMaxKeptFrames frames after the priced one, each with
//   - the same policy (the same object), light index and light position,
//     the same objects (mesh objects, transforms, occluder flags), window
//     size, near plane and depth-limited verdict as the priced frame;
//   - every occluder's method Z-fail or ZP+ with the clipped-sides cap:
//     candidates on every frame, right wherever Z-fail is and admitted by no
//     per-frame test (Z-pass needs the exact test or the certain cull, the
//     paper cap the crack model, AtomicZP its conditions), so a kept choice
//     is one the policy offers on the frame it is drawn on;
//   - at the priced frame, every other choice the decision weighed (the best
//     frame of another frame option, the frame with the exact Z-pass test
//     where it was weighed and not run, or one occluder with another of its
//     candidates) priced dearer by at least kMargin of the chosen frame's
//     price, both as the choice weighs them, without the coverage every
//     candidate draws alike (PolicyDecision::choice_margin).
// A kept choice is then as right as a priced one; only its cost can differ,
// where the prices crossed within a few frames.  Not thread-safe: one per
// frame loop, whose base settings stay the same.
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <vector>

#include "nearcap/gl/shadow_methods.hpp"
#include "nearcap/scene/scene.hpp"

namespace nearcap::analysis {

struct SwitchPolicy;

class KeptChoices {
 public:
  static constexpr int kMaxKeptFrames = 2;  // frames after the priced one
  static constexpr double kMargin = 0.2;    // of the chosen frame's price, as the choice weighs it

  // What a frame gets from the priced frame before it.
  struct Choice {
    std::vector<gl::ShadowMethod> object_methods;  // one per scene object
    gl::LightProjection projection = gl::LightProjection::Paper;
    int frames_since_priced = 0;  // 1 on the frame after the priced one
  };
  // Where the frame (`scene`, `light`, with the frame's near plane and
  // depth-limited verdict, as decide() settles them before pricing) may
  // take the choice kept for its light: that choice, counted as one more
  // frame.  Else nothing (the frame is priced).
  std::optional<Choice> take(const SwitchPolicy& policy, const Scene& scene, std::size_t light,
                             gl::NearPlane near_plane, bool depth_limited);
  // A priced frame's choice and margin (NaN: none): kept for the next frames
  // where it qualifies (above), else the light's kept choice is dropped.
  void remember(const SwitchPolicy& policy, const Scene& scene, std::size_t light, gl::NearPlane near_plane,
                bool depth_limited, const std::vector<gl::ShadowMethod>& object_methods, gl::LightProjection projection,
                double margin);

  std::size_t frames_kept() const { return frames_kept_; }  // frames given a kept choice, all lights

 private:
  struct ObjectKey {
    std::shared_ptr<const TriangleMesh> mesh;  // held: its address is not reused while kept
    Affine3d object_to_world;
    bool occluder = true;
  };
  struct Entry {
    const SwitchPolicy* policy = nullptr;
    std::size_t light = 0;
    Vec3d light_position;
    std::vector<ObjectKey> objects;
    int width = 0, height = 0;
    gl::NearPlane near_plane = gl::NearPlane::Scene;
    bool depth_limited = false;
    Choice choice;
  };
  bool same_frame_setup(const Entry& e, const SwitchPolicy& policy, const Scene& scene, std::size_t light,
                        gl::NearPlane near_plane, bool depth_limited) const;
  std::vector<Entry> entries_;  // one per light index at most
  std::size_t frames_kept_ = 0;
};

}  // namespace nearcap::analysis
