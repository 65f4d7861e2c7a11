// nearcap/io/scene_file.hpp — scene files (JSON, docs/scene-format.md) into Scene.
#pragma once

#include <map>
#include <memory>
#include <mutex>
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
// Throws nearcap::Error naming the file and the element.  Meshes come from
// `cache` when one is given (MeshCache, below).
class MeshCache;
Scene load_scene(const std::string& path, MeshCache* cache = nullptr);

// Meshes read once for many scene files: a sweep's frames of one camera path
// name the same 75k-triangle mesh hundreds of times.  Keyed by the resolved
// path made absolute (a scene read by a relative path and the same scene's
// text with absolute mesh paths share one entry); a file whose size or
// modification time changed is read again; an occluder's validation is done
// once too.  Thread-safe.
class MeshCache {
 public:
  // The mesh, read, with adjacency and face planes, validated when `occluder`.
  // Throws what reading or validating throws (the caller adds the context).
  std::shared_ptr<const TriangleMesh> get(const std::string& path, bool occluder);
  std::size_t reads() const;  // how many times a file was actually read
  // Asks bounds_outward_solids() of every occluder mesh read so far, so that
  // its first call (a large mesh's self-intersection test) is paid here and
  // not by the first frame that traces it (a sweep, before its timer).
  void decide_outward_solids() const;

 private:
  struct Entry {
    std::shared_ptr<TriangleMesh> mesh;
    long long size = -1, mtime_ns = -1;
    bool validated = false;
  };
  mutable std::mutex mutex_;
  std::map<std::string, Entry> entries_;
  std::size_t reads_ = 0;
};

// Same, from JSON text; mesh paths are resolved against `base_directory`;
// meshes come from `cache` when one is given.
Scene parse_scene(const std::string& json_text, const std::string& source, const std::string& base_directory,
                  MeshCache* cache = nullptr);

// Scene JSON text with each object's relative mesh path made absolute
// (against the directory of `scene_file`, where the text came from), so that
// the text describes the same scene from anywhere; nothing else changes.
// Malformed JSON: Error(Parse) naming `scene_file`.
std::string with_absolute_mesh_paths(const std::string& json_text, const std::string& scene_file);

}  // namespace nearcap
