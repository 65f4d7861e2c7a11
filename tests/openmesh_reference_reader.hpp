// OpenMesh's readers as a reference for nearcap's own on well-formed files
// (the differential mesh-reader test).  Never given outside data: OpenMesh's
// readers abort or crash on malformed input (see src/io/mesh_file.cpp).
#pragma once

#include <string>

#include "nearcap/scene/mesh.hpp"

namespace nearcap::test {

// Reads `bytes` in `format` ("obj", "ply" or "stl") with OpenMesh 9 into a
// TriangleMesh, every face as OpenMesh reports it; throws std::runtime_error
// when OpenMesh reports failure or a face is not a triangle.
TriangleMesh read_with_openmesh(const std::string& bytes, const std::string& format);

}  // namespace nearcap::test
