// nearcap/exact/light_validation.hpp — lights must lie strictly outside every occluder.
//
// A light on an occluder's surface makes "the side of a triangle the light is
// on" meaningless there; a light inside an occluder makes every shadow volume
// of that occluder cover the whole scene, which ZP+ (section 3.2) assumes never
// happens.  Both are rejected.  The test is exact: a light is on the surface
// when it lies in the closed triangle of some face; it is inside when the
// winding number of the closed mesh around it is non-zero, counted along a
// segment from the light to a point below the mesh's bounding box with the
// sample-point perturbation of perturbation.hpp.
#pragma once

#include <cstddef>

#include "nearcap/exact/camera_space.hpp"
#include "nearcap/scene/scene.hpp"

namespace nearcap {

enum class LightPlacement { Outside, OnSurface, Inside };

// Where light k lies relative to occluder o (which must be closed).  When
// OnSurface, *face (if given) receives a face that holds the light.
LightPlacement light_placement(const CameraSpaceScene& scene, std::size_t o, std::size_t light, FaceIndex* face,
                               FilterStats* stats);

// Throws Error(Light) naming the scene file, the light and the object.
void validate_lights(const Scene& scene, const CameraSpaceScene& camera_space);

// The float32 pipeline evaluates cubic expressions of camera-space coordinate
// differences (the facing test dot(cross(b - a, c - a), l - a)).  With every
// coordinate within 2^40, such a cubic stays below 6 (2^41)^3 < 2^126, inside
// float32's range (max 2^128).  Scenes beyond it are rejected.
inline constexpr double kFloatPipelineCoordinateLimit = 0x1p40;

// Throws Error(Range) naming the object (or light) whose camera-space
// coordinates exceed kFloatPipelineCoordinateLimit.
void validate_float_range(const Scene& scene, const CameraSpaceScene& camera_space);

// Everything load_scene() checks that needs camera-space geometry: the float
// range, then the lights' placement.
void validate_scene_geometry(const Scene& scene);

}  // namespace nearcap
