// OpenMesh meshes into nearcap (io/openmesh_adapter.hpp) and in-memory scenes
// (io/scene_builder.hpp): the same mesh as its file, the same checks as a file.
#include <gtest/gtest.h>
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include "nearcap/error.hpp"
#include "nearcap/io/mesh_file.hpp"
#include "nearcap/io/openmesh_adapter.hpp"
#include "nearcap/io/scene_builder.hpp"
#include "nearcap/io/scene_file.hpp"

namespace nearcap {
namespace {

struct DoubleTraits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
};
using TriMesh = OpenMesh::TriMesh_ArrayKernelT<DoubleTraits>;
using PolyMesh = OpenMesh::PolyMesh_ArrayKernelT<DoubleTraits>;

TriMesh openmesh_from(const TriangleMesh& m) {
  TriMesh out;
  std::vector<TriMesh::VertexHandle> v;
  for (const Vec3d& p : m.positions) v.push_back(out.add_vertex({p.x, p.y, p.z}));
  for (const auto& t : m.triangles) out.add_face(v[t[0]], v[t[1]], v[t[2]]);
  return out;
}

ErrorKind build_error(const SceneBuilder& b) {
  try {
    (void)b.build();
  } catch (const Error& e) {
    return e.kind();
  }
  ADD_FAILURE() << "accepted";
  return ErrorKind::Usage;
}

bool same_positions(const std::vector<Vec3d>& a, const std::vector<Vec3d>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t k = 0; k < a.size(); ++k)
    if (a[k].x != b[k].x || a[k].y != b[k].y || a[k].z != b[k].z) return false;
  return true;
}

const std::string kMeshes = std::string(NEARCAP_SOURCE_DIR) + "/data/meshes/";

TEST(OpenMeshAdapter, GivesTheSameMeshAsTheFile) {
  const TriangleMesh file = read_mesh(kMeshes + "torus.off");
  const TriangleMesh adapted = mesh_from_openmesh(openmesh_from(file), "torus (OpenMesh)");
  EXPECT_TRUE(same_positions(adapted.positions, file.positions));
  EXPECT_EQ(adapted.triangles, file.triangles);
  EXPECT_EQ(adapted.source, "torus (OpenMesh)");
}

TEST(OpenMeshAdapter, AQuadFaceIsNamed) {
  PolyMesh quad;
  std::vector<PolyMesh::VertexHandle> v;
  for (const auto& p : {OpenMesh::Vec3d(0, 0, 0), {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}) v.push_back(quad.add_vertex(p));
  quad.add_face(v);
  try {
    (void)mesh_from_openmesh(quad, "quad");
    FAIL() << "a quad was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Mesh);
    EXPECT_NE(std::string(e.what()).find("face 0 has 4 vertices"), std::string::npos) << e.what();
  }
}

TEST(SceneBuilder, BuildsTheSceneTheFileDescribes) {
  // data/scenes/case_d.json rebuilt in memory from its parts equals the file.
  const Scene file = load_scene(std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/case_d.json");
  SceneBuilder b("case_d in memory");
  b.camera(file.camera);
  for (const Light& l : file.lights) b.light(l.position);
  for (const SceneObject& o : file.objects) {
    const TriangleMesh mesh = mesh_from_openmesh(openmesh_from(*o.mesh), o.mesh_path);
    if (o.occluder)
      b.object(mesh, o.object_to_world);
    else
      b.receiver(mesh, o.object_to_world);
  }
  const Scene built = b.build();
  ASSERT_EQ(built.objects.size(), file.objects.size());
  for (std::size_t k = 0; k < built.objects.size(); ++k) {
    EXPECT_TRUE(same_positions(built.objects[k].mesh->positions, file.objects[k].mesh->positions));
    EXPECT_EQ(built.objects[k].mesh->neighbours, file.objects[k].mesh->neighbours);
    EXPECT_EQ(built.objects[k].occluder, file.objects[k].occluder);
  }
}

TEST(SceneBuilder, ChecksLikeAFile) {
  const Scene file = load_scene(std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/case_d.json");
  const TriangleMesh box = read_mesh(kMeshes + "box.off");
  auto base = [&] {
    SceneBuilder b("test scene");
    b.camera(file.camera).light(file.lights[0].position);
    return b;
  };
  // An open mesh as an occluder.
  TriangleMesh open = box;
  open.triangles.pop_back();
  EXPECT_EQ(build_error(base().object(open)), ErrorKind::Mesh);
  EXPECT_EQ(base().receiver(open).build().objects.size(), 1u) << "a receiver need not be closed";
  // A NaN coordinate, an index out of range.
  TriangleMesh nan = box;
  nan.positions[0].x = std::nan("");
  EXPECT_EQ(build_error(base().object(nan)), ErrorKind::NonFinite);
  TriangleMesh bad_index = box;
  bad_index.triangles[0][0] = 999;
  EXPECT_EQ(build_error(base().object(bad_index)), ErrorKind::Mesh);
  // A light inside the occluder.
  Affine3d around_light;
  for (int i = 0; i < 3; ++i) around_light.rows[i][3] = file.lights[0].position[i];
  EXPECT_EQ(build_error(base().object(box, around_light)), ErrorKind::Light);
  // A singular transform, a degenerate camera, nothing at all.
  Affine3d flat;
  flat.rows[2][2] = 0;
  EXPECT_EQ(build_error(base().object(box, flat)), ErrorKind::Schema);
  Camera degenerate = file.camera;
  degenerate.frustum.right = degenerate.frustum.left;
  EXPECT_EQ(build_error(SceneBuilder().camera(degenerate).light({0, 5, 0}).object(box)), ErrorKind::Camera);
  EXPECT_EQ(build_error(SceneBuilder().light({0, 5, 0}).object(box)), ErrorKind::Schema);
  // The message names the builder's source and the object.
  try {
    (void)base().receiver(box).object(open).build();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("test scene: objects[1] (occluder)"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace nearcap
