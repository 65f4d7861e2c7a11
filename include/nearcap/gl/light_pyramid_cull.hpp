// nearcap/gl/light_pyramid_cull.hpp — which occluders the near-cap pass may
// skip: a double-precision filter that never needs the exact kernel.
//
// A point q of the near rectangle is in an occluder's shadow volume exactly
// when the segment from the light to q meets the occluder, so an occluder
// that holds no point of the light pyramid (the light and the near
// rectangle: the union of those segments) has an empty near-cap, and its
// near-cap pass adds nothing at any pixel (exact/light_pyramid.hpp decides
// the same question exactly, for the switch policy).  The clipped-sides cap
// pass (near_plane_cap.hpp) otherwise evaluates z + w at every vertex of
// an occluder whose box straddles the near plane, and clips and fans what
// reaches it, only to find nothing in the viewport: on the bundled paths,
// without this filter, 11 % of the frame's time where Z-pass is right.
//
// The filter answers "certainly misses" only with room to spare for the
// float pipeline's own error, since skipping must not change the float
// frame: the near rectangle is grown by the cap's shortcut margin (a
// twentieth of the viewport and 8 pixels on each side, near_plane_cap.hpp),
// each box is grown by a float32 rounding bound of the coordinates that
// reach the vertex program (object space, world and camera space, the
// light), and nothing is skipped where the near plane is closer to the eye
// than 2^-10 of the occluder's depth (the float32 z + w there is known to
// fewer bits than the cut needs; the tiny-near kind of the sampler).  Boxes
// first (the mesh's, then its chunks of FacePlanes::kFacesPerChunk faces),
// then each face of a chunk not decided whole, by its three vertices with
// its chunk's bound (the triangle the pipeline draws is the one their
// images span): each certainly outside one of the pyramid's six planes
// (four sides through the light, the near plane, and its parallel through
// the light).
#pragma once

#include <cstddef>

#include "nearcap/scene/scene.hpp"

namespace nearcap::gl {

// True when scene.objects[object] certainly holds no point of the light
// pyramid of `light` (world space) over scene.camera's near rectangle grown
// by margin_x, margin_y (NDC units on each side; the near-cap pass passes
// near_plane_cap_margin), with the float allowances
// above; false when it may (or the object has no face chunks, or the light
// lies within rounding of the near plane).  With `faces_examined`, stores
// there the faces whose own bounds it tested (those of the chunks whose box
// it could not decide whole, up to the first face that may meet the
// pyramid): the part of its work that grows with the mesh, what the
// clipped-sides cap's cost is priced by (analysis/device_profile.hpp,
// CpuTaskWork::examined); 0 where the mesh's box or the chunks' boxes
// decide.
bool certainly_misses_light_pyramid(const Scene& scene, std::size_t object, const Vec3d& light, double margin_x,
                                    double margin_y, std::size_t* faces_examined = nullptr);

}  // namespace nearcap::gl
