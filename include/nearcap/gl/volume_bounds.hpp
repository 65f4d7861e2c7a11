// nearcap/gl/volume_bounds.hpp — where one occluder's shadow volume can
// change a pixel: the scissor rectangle and the depth-bounds range of volume
// culling (EmulationSettings::volume_culling, the paper's speed argument's
// last two options).
//
// All of one occluder's draws (its near-cap, sides, caps, corrective quads,
// the preload pass) add at a pixel a net count that is 0 unless the visible
// surface point s there lies in the occluder's shadow volume V (for every
// method but Z-pass, which also counts -1 where the near plane's point q
// there lies in V).  Stencil increments wrap, so dropping every
// fragment of those draws at a pixel where both lie outside V leaves the
// final stencil as it was.  The scissor test drops the pixels outside a
// rectangle, the depth bounds test (GL_EXT_depth_bounds_test) those whose
// stored depth lies outside a range, both before the stencil test.
//
// Both come from a convex region R that holds V ∩ B, B the box of every
// object and of the near rectangle (s and q lie in B): the polytope bounded
// by B's six planes, the facets of the cone from the light l through Q (the
// occluder's object-space box mapped to world space) and the plane across l's axis
// to Q through Q's nearest corner (V lies in {l + t (p - l) : p in Q,
// t >= 1}).  Its vertices, by enumerating every triple of its at most 19
// planes in double; those in front of the near plane and the near plane's
// cuts of every pair of them, through the frame's float32 projection in
// double, give the rectangle and the range.  The cone's facets are the
// planes through l and an edge of Q with every corner of Q on one side up to
// double rounding.  The float pipeline's volume and surfaces are not the
// exact ones: taking its positions, matrices and light within e = 2^-20 of
// the largest coordinate of the exact ones (float32 rounding; tenths of a
// unit at 3e6), its volume {l' + t (p' - l')} lies within (2t - 1) e of the
// exact volume, so B's planes and the plane across the axis move out by e
// and the cone's facets by 2 t_max e, t_max the farthest B reaches along
// the cone in units of l's distance to Q.  Window-space allowances: the
// rectangle widened by 2 pixels, the range by 2^-16 plus 8 steps of a
// 24-bit buffer.  e and these allowances are estimates of the float
// pipeline's error, not proofs (docs/findings/volume-culling.md measures
// them).  Nothing is bounded where the light lies in, on or within 4e of
// Q's box.
#pragma once

#include <cstddef>
#include <optional>

#include "nearcap/gl/float_transforms.hpp"
#include "nearcap/gl/pipeline.hpp"
#include "nearcap/scene/scene.hpp"

namespace nearcap::gl {

struct VolumeBounds {
  PixelRect scissor;                    // may be empty: no pixel of the viewport can change
  double depth_min = 0, depth_max = 1;  // window depth, within [0, 1]
  // R reaches the near plane.  Then Z-pass (no near-cap) counts -1 where
  // the near plane's point q lies in V and s does not: a count the depth
  // bounds, which test s alone, would drop, so Z-pass draws keep none.
  bool meets_near_plane = false;
};

// The bounds of scene.objects[object]'s shadow volume from `light` (world
// space), for the frame drawn with `projection` (camera space to clip
// space, as uploaded) in `mapping`; nothing when R is unbounded.
std::optional<VolumeBounds> shadow_volume_bounds(const Scene& scene, std::size_t object, const Vec3d& light,
                                                 const Mat4f& projection, DepthMapping mapping);

}  // namespace nearcap::gl
