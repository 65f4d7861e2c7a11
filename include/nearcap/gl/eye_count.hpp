// nearcap/gl/eye_count.hpp — AtomicZP's per-frame constant in float32: how
// many of the light's shadow volumes contain the eye.
//
// Depth-clamped Z-pass (no near clipping) counts, at each pixel, the volume
// boundaries crossed between the eye and the visible surface: the surface's
// count minus the eye's.  AtomicZP (Usta, Scandolo, Billeter, Marroquim and
// Eisemann, HPG 2019) supplies the eye's count as one constant per frame,
// counted on the GPU into an atomic counter.  The paper's text is not in the
// material nearcap was built from; this is the project's reconstruction
// (docs/atomiczp.md names each step that is its own reading):
//
//   one invocation per occluder triangle (a vertex, geometry or compute
//   stage over the mesh), in camera space, where the eye is the origin:
//     p_k   = MV * v_k                 (transform(), the emulation's order and
//                                       Arithmetic, MV = view * object as the
//                                       vertex programs' modelview)
//     n     = (p1 - p0) x (p2 - p0)
//     lit   = h * dot(n, l - p0) > 0   (the triangle faces the light; h = +1,
//                                       or -1 where MV mirrors)
//     eye   = h * dot(n, 0 - p0) < 0   (the eye behind its plane)
//     s_k   = dot(l, p_k x p_k+1)      (the line eye->light against edge k)
//     crossed = lit && eye && s_0, s_1, s_2 all > 0 or all < 0
//   atomicCounterIncrement once per crossed triangle.
// l is the light in camera space as the engine's silhouette extraction has
// it (light_in_camera_space: view rounded to float32 times the light rounded
// to float32).  Every product and sum is float32, left to right, or fused
// multiply-adds with Arithmetic::Fused (a shader compiler may contract).  A
// float zero in any test counts as not crossed (the strict comparisons
// above): the eye in a triangle's plane, or the segment through an edge, adds
// nothing.  With closed, consistently wound occluders the crossings of
// light-facing triangles are the number of volumes containing the eye (the
// same count the exact reference makes at a sample point:
// exact/eye_count.hpp).
#pragma once

#include <cstddef>
#include <vector>

#include "nearcap/gl/float_transforms.hpp"
#include "nearcap/scene/scene.hpp"

namespace nearcap::gl {

struct FloatEyeCount {
  std::size_t count = 0;      // light-facing occluder triangles the segment eye -> light crosses
  std::size_t triangles = 0;  // occluder triangles tested: the pass's invocations
};

// Over every occluder of the scene, or over the listed objects (occluders,
// scene indices: a frame that draws only those with AtomicZP).
FloatEyeCount float_eye_count(const Scene& scene, std::size_t light, Arithmetic arithmetic = Arithmetic::Separate);
FloatEyeCount float_eye_count(const Scene& scene, std::size_t light, const std::vector<std::size_t>& objects,
                              Arithmetic arithmetic = Arithmetic::Separate);

// What the pass takes for one occluder besides its vertices: the float32
// modelview (view * object, multiply() in `arithmetic`, as the vertex
// programs' modelview) and whether it mirrors (the sign of its 3x3
// determinant in float32: h = -1).  A GPU pass gets these as uniforms
// (render/eye_count_pass.hpp).
struct EyeCountObject {
  Mat4f modelview;
  bool mirrored = false;
};
EyeCountObject eye_count_object(const Scene& scene, std::size_t object, Arithmetic arithmetic = Arithmetic::Separate);

// One triangle's test, camera-space float32 inputs (the eye at the origin):
// what one invocation of the pass decides.  `mirrored`: the modelview
// reverses orientation (h = -1).
bool float_eye_segment_crosses(const Vec4f& p0, const Vec4f& p1, const Vec4f& p2, const Vec4f& light, bool mirrored,
                               Arithmetic arithmetic = Arithmetic::Separate);

}  // namespace nearcap::gl
