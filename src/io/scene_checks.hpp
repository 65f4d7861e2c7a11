// Checks shared by the scene file reader and the in-memory SceneBuilder
// (private to io/): what makes a camera, a transform and a mesh acceptable.
#pragma once

#include <string>

#include "nearcap/error.hpp"
#include "nearcap/scene/scene.hpp"

namespace nearcap::scene_checks {

// Throws Error(kind, "source: where: what").
[[noreturn]] void fail(const std::string& source, ErrorKind kind, const std::string& where, const std::string& what);

// Finite, within the float32 pipeline's range, ordered, non-degenerate in float32.
void check_frustum(const Frustum& f, const std::string& source, const std::string& where);

// The 3x3 linear part has a non-zero exact determinant.
bool invertible(const Affine3d& m);

}  // namespace nearcap::scene_checks
