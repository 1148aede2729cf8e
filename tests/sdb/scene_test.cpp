#include "sdb/scene.h"

#include <gtest/gtest.h>

#include <map>

#include <glm/gtc/matrix_transform.hpp>

#include "sdb/features.h"
#include "sdb/material_presets.h"
#include "sdb/scene_stats.h"

namespace fly::sdb {
namespace {

// A unit quad in the local XZ plane (y = 0), facing +Y.
Mesh quad(const std::string& name, MaterialId material) {
  Mesh m;
  m.name = name;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 0, -1}, {0, 0, -1}};
  m.normals.assign(4, vec3(0, 1, 0));
  m.indices = {0, 1, 2, 0, 2, 3};
  m.material = material;
  return m;
}

TEST(SceneIds, AreStableAndNeverReused) {
  Scene s;
  const NodeId a = s.addNode({.name = "a"}).id;
  const NodeId b = s.addNode({.name = "b"}).id;
  EXPECT_NE(a, b);
  s.removeNode(a);
  const NodeId c = s.addNode({.name = "c"}).id;
  EXPECT_NE(c, a);
  EXPECT_NE(c, b);
  EXPECT_EQ(s.node(b).name, "b");
  EXPECT_THROW(s.node(a), std::out_of_range);
}

TEST(SceneHierarchy, WorldTransformComposesParentsAndForEachNodeVisitsParentsFirst) {
  Scene s;
  const NodeId root = s.addNode({.name = "root", .parentFromLocal = glm::translate(mat4(1), vec3(10, 0, 0))}).id;
  const NodeId child =
      s.addNode({.name = "child", .parent = root, .parentFromLocal = glm::scale(mat4(1), vec3(2.0f))}).id;
  const NodeId leaf =
      s.addNode({.name = "leaf", .parent = child, .parentFromLocal = glm::translate(mat4(1), vec3(0, 1, 0))}).id;
  const vec4 p = s.worldFromLocal(leaf) * vec4(1, 0, 0, 1);
  EXPECT_EQ(vec3(p), vec3(12, 2, 0));  // translate(10) · scale(2) · translate(0,1,0) · (1,0,0)
  std::vector<std::string> order;
  s.forEachNode([&](NodeId id, const mat4& worldFromLocal) {
    order.push_back(s.node(id).name);
    EXPECT_EQ(worldFromLocal, s.worldFromLocal(id));
  });
  EXPECT_EQ(order, (std::vector<std::string>{"root", "child", "leaf"}));
  EXPECT_EQ(s.node(root).children, std::vector<NodeId>{child});
}

TEST(SceneChangeSet, EveryEditNamesWhatChanged) {
  Scene s;
  const Added<MaterialId> mat = s.addMaterial(findMaterialPreset("concrete")->material);
  EXPECT_EQ(mat.changes.changes, (std::vector<Change>{{EntityType::kMaterial, mat.id.value, ChangeKind::kAdded}}));
  const Added<MeshId> mesh = s.addMesh(quad("floor", mat.id));
  const NodeId root = s.addNode({.name = "root"}).id;
  const Added<NodeId> node = s.addNode({.name = "floor", .parent = root, .meshes = {mesh.id}});
  EXPECT_EQ(node.changes.changes,
            (std::vector<Change>{{EntityType::kNode, node.id.value, ChangeKind::kAdded},
                                 {EntityType::kNode, root.value, ChangeKind::kModified, Aspect::kHierarchy}}));

  EXPECT_EQ(s.setNodeTransform(node.id, glm::translate(mat4(1), vec3(1))).changes,
            (std::vector<Change>{{EntityType::kNode, node.id.value, ChangeKind::kModified, Aspect::kTransform}}));
  Material red = s.material(mat.id);
  red.diffuseColor = Rgb(0.5f, 0.0f, 0.0f);
  const ChangeSet cs = s.setMaterial(mat.id, red);
  EXPECT_TRUE(cs.touches(EntityType::kMaterial));
  EXPECT_FALSE(cs.touches(EntityType::kMesh));
  EXPECT_EQ(s.material(mat.id).diffuseColor, Rgb(0.5f, 0.0f, 0.0f));
  EXPECT_EQ(s.setMeshMaterial(mesh.id, MaterialId{}).changes,
            (std::vector<Change>{
                {EntityType::kMesh, mesh.id.value, ChangeKind::kModified, Aspect::kMaterialAssignment}}));
  EXPECT_EQ(s.setSite({.latitudeDeg = 60.17}).changes,
            (std::vector<Change>{{EntityType::kSite, 0, ChangeKind::kModified}}));
  EXPECT_TRUE(s.hasSite());
  EXPECT_TRUE(s.setTime({"2026-06-21T12:00"}).touches(EntityType::kTime));
  EXPECT_TRUE(s.setSky({.model = SkyModel::kClear, .sun = true}).touches(EntityType::kSky));

  const ChangeSet removed = s.removeNode(root);
  EXPECT_EQ(removed.changes.size(), 2u);
  EXPECT_TRUE(s.roots().empty());
  EXPECT_EQ(s.meshes().size(), 1u);  // meshes outlive the nodes that placed them
}

TEST(SceneChangeSet, InvalidEditsAreRejectedAndLeaveTheSceneUnchanged) {
  Scene s;
  const MaterialId mat = s.addMaterial(Material{}).id;
  Material bad;
  bad.ior = 9.0f;
  EXPECT_THROW(s.setMaterial(mat, bad), std::invalid_argument);
  EXPECT_EQ(s.material(mat).ior, 1.5f);
  Mesh broken = quad("q", mat);
  broken.indices.push_back(7);
  broken.indices.push_back(0);
  broken.indices.push_back(1);
  EXPECT_THROW(s.addMesh(broken), std::invalid_argument);
  EXPECT_THROW(s.addNode({.name = "n", .parent = NodeId{999}}), std::invalid_argument);
  EXPECT_THROW(s.addNode({.name = "n", .parentFromLocal = mat4(std::nanf(""))}), std::invalid_argument);
  EXPECT_TRUE(s.nodes().empty());
}

TEST(SceneStats, CountsInstancesAndWorldBounds) {
  Scene s;
  const MaterialId glass = s.addMaterial(findMaterialPreset("clear-glass")->material).id;
  const MaterialId concrete = s.addMaterial(findMaterialPreset("concrete")->material).id;
  const MeshId pane = s.addMesh(quad("pane", glass)).id;
  const MeshId floor = s.addMesh(quad("floor", concrete)).id;
  s.addNode({.name = "a", .meshes = {pane, floor}});
  s.addNode({.name = "b", .parentFromLocal = glm::translate(mat4(1), vec3(5, 2, 0)), .meshes = {floor}});
  const LightId lamp = s.addLight({.name = "lamp", .intensity = 100.0f}).id;
  s.addNode({.name = "lamp", .light = lamp});
  Material glow;
  glow.emissionLuminance = Rgb(1000.0f);
  const MeshId panel = s.addMesh(quad("panel", s.addMaterial(glow).id)).id;
  s.addNode({.name = "panel", .parentFromLocal = glm::translate(mat4(1), vec3(0, 1, 0)), .meshes = {panel}});
  const SceneStats st = computeStats(s);
  EXPECT_EQ(st.nodes, 4u);
  EXPECT_EQ(st.meshes, 3u);
  EXPECT_EQ(st.meshInstances, 4u);
  EXPECT_EQ(st.triangles, 8u);
  EXPECT_EQ(st.materialsByClass.at("emitter"), 1u);
  EXPECT_EQ(st.materialsByClass.at("glass"), 1u);
  EXPECT_EQ(st.materialsByClass.at("stone"), 1u);
  EXPECT_EQ(st.lightsByType.at("point"), 1u);
  EXPECT_EQ(st.emissiveMeshes, 1u);
  EXPECT_EQ(st.boundsWorldM.min, vec3(0, 0, -1));
  EXPECT_EQ(st.boundsWorldM.max, vec3(6, 2, 0));
}

TEST(SceneFeatures, DetectedFromWhatTheSceneContains) {
  Scene s;
  EXPECT_TRUE(computeFeatures(s).names().empty());
  const MaterialId steel = s.addMaterial(findMaterialPreset("polished-metal")->material).id;
  const MeshId mirror = s.addMesh(quad("mirror", steel)).id;
  Mesh bent = quad("bent", steel);
  bent.positions[2].y = 0.5f;  // lifts one corner: no longer planar
  const MeshId curved = s.addMesh(bent).id;
  const MeshId unplaced = s.addMesh(quad("unplaced", s.addMaterial(findMaterialPreset("clear-glass")->material).id)).id;
  (void)unplaced;
  s.addNode({.name = "m", .meshes = {mirror}});
  SceneFeatures f = computeFeatures(s);
  EXPECT_TRUE(f.planarReflectors);
  EXPECT_FALSE(f.curvedReflectors);
  EXPECT_FALSE(f.transmissiveMaterials);  // the glass mesh is not placed by any node
  const std::string steelName = s.material(steel).name;
  EXPECT_EQ(f.engineReflections, (std::map<std::string, std::string>{{steelName, "planar"}}));
  s.addNode({.name = "c", .meshes = {curved}});
  f = computeFeatures(s);
  EXPECT_TRUE(f.curvedReflectors);
  EXPECT_EQ(f.engineReflections.at(steelName), "planar, cubemap");  // the flat mirror and the bent one
  s.setSky({.model = SkyModel::kCie, .sun = true});
  s.setMeshTwoSided(mirror, true);
  EXPECT_EQ(computeFeatures(s).names(),
            (std::vector<std::string>{"sun", "sky", "two-sided-surfaces", "planar-reflectors", "curved-reflectors"}));
  Material fogged = s.material(steel);
  fogged.reflectionFogDistanceM = 3.0f;
  s.setMaterial(steel, fogged);
  EXPECT_TRUE(computeFeatures(s).reflectionFog);
  EXPECT_EQ(computeFeatures(s).names().back(), "reflection-fog");
}

TEST(SceneCamera, LookAtPlacesTheCameraLookingDownMinusZ) {
  const mat4 m = lookAtTransform(vec3(1, 2, 3), vec3(1, 2, -7), vec3(0, 1, 0));
  EXPECT_EQ(vec3(m[3]), vec3(1, 2, 3));
  EXPECT_NEAR(glm::distance(vec3(m * vec4(0, 0, -1, 0)), vec3(0, 0, -1)), 0.0f, 1e-6f);
  EXPECT_NEAR(glm::distance(vec3(m * vec4(0, 1, 0, 0)), vec3(0, 1, 0)), 0.0f, 1e-6f);
  EXPECT_THROW(lookAtTransform(vec3(1), vec3(1), vec3(0, 1, 0)), std::invalid_argument);
  EXPECT_THROW(lookAtTransform(vec3(0), vec3(0, 5, 0), vec3(0, 1, 0)), std::invalid_argument);
}

}  // namespace
}  // namespace fly::sdb
