#include "sdb/scene.h"

#include <algorithm>
#include <stdexcept>

namespace fly::sdb {

namespace {

template <class Map, class IdT>
auto& mustFind(Map& map, IdT id, const char* what) {
  auto it = map.find(id);
  if (it == map.end()) {
    throw std::invalid_argument(std::string("Scene: no ") + what + " with id " + std::to_string(id.value));
  }
  return it->second;
}

ChangeSet single(EntityType type, uint32_t id, ChangeKind kind, Aspect aspect = Aspect::kAll) {
  ChangeSet cs;
  cs.add({type, id, kind, aspect});
  return cs;
}

void requireValid(const std::string& problem, const char* what) {
  if (!problem.empty()) throw std::invalid_argument(std::string("Scene: invalid ") + what + ": " + problem);
}

template <class IdT>
IdT firstNamed(const auto& map, const std::string& name) {
  for (const auto& [id, entity] : map) {
    if (entity.name == name) return id;
  }
  return IdT{};
}

}  // namespace

Added<TextureId> Scene::addTexture(Texture t) {
  const TextureId id{nextId_++};
  textures_.emplace(id, std::move(t));
  return {id, single(EntityType::kTexture, id.value, ChangeKind::kAdded)};
}

Added<MaterialId> Scene::addMaterial(Material m) {
  requireValid(validate(m), "material");
  const MaterialId id{nextId_++};
  materials_.emplace(id, std::move(m));
  return {id, single(EntityType::kMaterial, id.value, ChangeKind::kAdded)};
}

Added<MeshId> Scene::addMesh(Mesh m) {
  requireValid(validate(m), "mesh");
  if (m.material) mustFind(materials_, m.material, "material");
  const MeshId id{nextId_++};
  meshes_.emplace(id, std::move(m));
  return {id, single(EntityType::kMesh, id.value, ChangeKind::kAdded)};
}

Added<CameraId> Scene::addCamera(Camera c) {
  const CameraId id{nextId_++};
  cameras_.emplace(id, std::move(c));
  return {id, single(EntityType::kCamera, id.value, ChangeKind::kAdded)};
}

Added<LightId> Scene::addLight(Light l) {
  requireValid(validate(l), "light");
  const LightId id{nextId_++};
  lights_.emplace(id, std::move(l));
  return {id, single(EntityType::kLight, id.value, ChangeKind::kAdded)};
}

Added<NodeId> Scene::addNode(Node n) {
  if (!n.children.empty()) throw std::invalid_argument("Scene::addNode: children are added through their parent");
  for (MeshId m : n.meshes) mustFind(meshes_, m, "mesh");
  if (n.camera) mustFind(cameras_, n.camera, "camera");
  if (n.light) mustFind(lights_, n.light, "light");
  if (!isFinite(n.parentFromLocal)) throw std::invalid_argument("Scene::addNode: transform is not finite");
  const NodeId id{nextId_++};
  ChangeSet cs = single(EntityType::kNode, id.value, ChangeKind::kAdded);
  if (n.parent) {
    mustFind(nodes_, n.parent, "parent node").children.push_back(id);
    cs.add({EntityType::kNode, n.parent.value, ChangeKind::kModified, Aspect::kHierarchy});
  } else {
    roots_.push_back(id);
  }
  nodes_.emplace(id, std::move(n));
  return {id, std::move(cs)};
}

ChangeSet Scene::setMaterial(MaterialId id, Material m) {
  requireValid(validate(m), "material");
  mustFind(materials_, id, "material") = std::move(m);
  return single(EntityType::kMaterial, id.value, ChangeKind::kModified);
}

ChangeSet Scene::setMeshMaterial(MeshId mesh, MaterialId material) {
  if (material) mustFind(materials_, material, "material");
  mustFind(meshes_, mesh, "mesh").material = material;
  return single(EntityType::kMesh, mesh.value, ChangeKind::kModified, Aspect::kMaterialAssignment);
}

ChangeSet Scene::setMeshTwoSided(MeshId mesh, bool twoSided) {
  mustFind(meshes_, mesh, "mesh").twoSided = twoSided;
  return single(EntityType::kMesh, mesh.value, ChangeKind::kModified);
}

ChangeSet Scene::setMeshLightTexture(MeshId mesh, LightTextureRequest request) {
  mustFind(meshes_, mesh, "mesh").lightTexture = request;
  return single(EntityType::kMesh, mesh.value, ChangeKind::kModified);
}

ChangeSet Scene::setNodeTransform(NodeId id, const mat4& parentFromLocal) {
  if (!isFinite(parentFromLocal)) throw std::invalid_argument("Scene::setNodeTransform: transform is not finite");
  mustFind(nodes_, id, "node").parentFromLocal = parentFromLocal;
  return single(EntityType::kNode, id.value, ChangeKind::kModified, Aspect::kTransform);
}

ChangeSet Scene::setLight(LightId id, Light l) {
  requireValid(validate(l), "light");
  mustFind(lights_, id, "light") = std::move(l);
  return single(EntityType::kLight, id.value, ChangeKind::kModified);
}

ChangeSet Scene::setCamera(CameraId id, Camera c) {
  mustFind(cameras_, id, "camera") = std::move(c);
  return single(EntityType::kCamera, id.value, ChangeKind::kModified);
}

ChangeSet Scene::setSite(const Site& site) {
  site_ = site;
  hasSite_ = true;
  return single(EntityType::kSite, 0, ChangeKind::kModified);
}

ChangeSet Scene::setTime(const SiteTime& time) {
  time_ = time;
  return single(EntityType::kTime, 0, ChangeKind::kModified);
}

ChangeSet Scene::setSky(const SkySettings& sky) {
  sky_ = sky;
  return single(EntityType::kSky, 0, ChangeKind::kModified);
}

ChangeSet Scene::setBakeSettings(const BakeSettings& bake) {
  bake_ = bake;
  return single(EntityType::kBake, 0, ChangeKind::kModified);
}

ChangeSet Scene::setPortals(std::vector<Portal> portals) {
  for (const Portal& p : portals) {
    if (const std::optional<PortalProblem> problem = checkPortal(p.cornersM)) {
      requireValid(problem->message, ("portal \"" + p.name + "\"").c_str());
    }
  }
  portals_ = std::move(portals);
  return single(EntityType::kPortals, 0, ChangeKind::kModified);
}

ChangeSet Scene::removeNode(NodeId id) {
  const Node& n = mustFind(nodes_, id, "node");
  ChangeSet cs;
  if (n.parent) {
    auto& siblings = nodes_.at(n.parent).children;
    siblings.erase(std::remove(siblings.begin(), siblings.end(), id), siblings.end());
    cs.add({EntityType::kNode, n.parent.value, ChangeKind::kModified, Aspect::kHierarchy});
  } else {
    roots_.erase(std::remove(roots_.begin(), roots_.end(), id), roots_.end());
  }
  std::vector<NodeId> stack{id};
  while (!stack.empty()) {
    const NodeId cur = stack.back();
    stack.pop_back();
    const Node& c = nodes_.at(cur);
    stack.insert(stack.end(), c.children.begin(), c.children.end());
    cs.add({EntityType::kNode, cur.value, ChangeKind::kRemoved});
    nodes_.erase(cur);
  }
  return cs;
}

const Material& Scene::material(MaterialId id) const {
  static const Material kDefault = [] {
    Material m;
    m.name = "default";
    return m;
  }();
  if (!id) return kDefault;
  return materials_.at(id);
}

mat4 Scene::worldFromLocal(NodeId id) const {
  mat4 m(1.0f);
  for (NodeId cur = id; cur; cur = nodes_.at(cur).parent) m = nodes_.at(cur).parentFromLocal * m;
  return m;
}

MaterialId Scene::findMaterial(const std::string& name) const { return firstNamed<MaterialId>(materials_, name); }
NodeId Scene::findNode(const std::string& name) const { return firstNamed<NodeId>(nodes_, name); }
MeshId Scene::findMesh(const std::string& name) const { return firstNamed<MeshId>(meshes_, name); }

}  // namespace fly::sdb
