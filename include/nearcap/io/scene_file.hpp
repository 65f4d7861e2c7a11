// nearcap/io/scene_file.hpp — scene files (JSON, README "Scene format") into Scene.
#pragma once

#include <string>

#include "nearcap/scene/scene.hpp"

namespace nearcap {

// Reads and validates a scene file: JSON syntax and schema (unknown keys are an
// error naming them), finiteness, camera (non-degenerate frustum, invertible
// view, non-zero viewport), object transforms (invertible), meshes (read, and
// validated as closed outward 2-manifolds when they are occluders).  The
// position of lights relative to occluders needs exact geometry and is checked
// by validate_scene_geometry() (light_validation.hpp), which load_scene() calls
// last, with the float32 range check.
// Throws nearcap::Error naming the file and the element.
Scene load_scene(const std::string& path);

// Same, from JSON text; mesh paths are resolved against `base_directory`.
Scene parse_scene(const std::string& json_text, const std::string& source, const std::string& base_directory);

}  // namespace nearcap
