// The Scene Description Database: engine-neutral, physical, the single source of truth (docs/architecture.md).
// Entities are stored by stable id; every edit returns a ChangeSet naming what changed.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "sdb/bake_settings.h"
#include "sdb/camera.h"
#include "sdb/change_set.h"
#include "sdb/light.h"
#include "sdb/material.h"
#include "sdb/mesh.h"
#include "sdb/node.h"
#include "sdb/portal.h"
#include "sdb/site.h"
#include "sdb/texture.h"

namespace fly::sdb {

// The id of an added entity and the change that added it.
template <class IdT>
struct Added {
  IdT id;
  ChangeSet changes;
};

class Scene {
 public:
  // --- Additions. Preconditions (referenced ids exist, valid parameters) throw std::invalid_argument.
  Added<TextureId> addTexture(Texture t);
  Added<MaterialId> addMaterial(Material m);
  Added<MeshId> addMesh(Mesh m);
  Added<CameraId> addCamera(Camera c);
  Added<LightId> addLight(Light l);
  // Adds `n` under n.parent (0 = a new root); n.children must be empty.
  Added<NodeId> addNode(Node n);

  // --- Edits.
  ChangeSet setMaterial(MaterialId id, Material m);
  ChangeSet setMeshMaterial(MeshId mesh, MaterialId material);
  ChangeSet setMeshTwoSided(MeshId mesh, bool twoSided);
  ChangeSet setMeshLightTexture(MeshId mesh, LightTextureRequest request);
  ChangeSet setNodeTransform(NodeId id, const mat4& parentFromLocal);
  ChangeSet setLight(LightId id, Light l);
  ChangeSet setCamera(CameraId id, Camera c);
  ChangeSet setSite(const Site& site);
  ChangeSet setTime(const SiteTime& time);
  ChangeSet setSky(const SkySettings& sky);
  ChangeSet setBakeSettings(const BakeSettings& bake);
  // Replaces the declared sky portals; each must pass checkPortal.
  ChangeSet setPortals(std::vector<Portal> portals);
  // Removes a node and its subtree (meshes, lights and cameras stay; they may be shared).
  ChangeSet removeNode(NodeId id);

  // --- Access. The at-accessors throw std::out_of_range for an unknown id.
  const Node& node(NodeId id) const { return nodes_.at(id); }
  const Mesh& mesh(MeshId id) const { return meshes_.at(id); }
  const Material& material(MaterialId id) const;  // id 0 = the default material
  const Texture& texture(TextureId id) const { return textures_.at(id); }
  const Light& light(LightId id) const { return lights_.at(id); }
  const Camera& camera(CameraId id) const { return cameras_.at(id); }

  const std::map<NodeId, Node>& nodes() const { return nodes_; }
  const std::map<MeshId, Mesh>& meshes() const { return meshes_; }
  const std::map<MaterialId, Material>& materials() const { return materials_; }
  const std::map<TextureId, Texture>& textures() const { return textures_; }
  const std::map<LightId, Light>& lights() const { return lights_; }
  const std::map<CameraId, Camera>& cameras() const { return cameras_; }
  const std::vector<NodeId>& roots() const { return roots_; }

  const Site& site() const { return site_; }
  bool hasSite() const { return hasSite_; }
  const SiteTime& time() const { return time_; }
  const SkySettings& sky() const { return sky_; }
  const BakeSettings& bakeSettings() const { return bake_; }
  const std::vector<Portal>& portals() const { return portals_; }

  // Product of parentFromLocal from the root down to `id`.
  mat4 worldFromLocal(NodeId id) const;

  // Calls f(nodeId, worldFromLocal) for every node, parents before children, roots in insertion order.
  template <class F>
  void forEachNode(F&& f) const {
    for (NodeId r : roots_) visit(r, mat4(1.0f), f);
  }

  // The file the scene was loaded from ("" when built in code); relative paths in it resolve against its folder.
  std::filesystem::path sourcePath;

  // Lookups by name (first match in id order); 0 when none.
  MaterialId findMaterial(const std::string& name) const;
  NodeId findNode(const std::string& name) const;
  MeshId findMesh(const std::string& name) const;

 private:
  template <class F>
  void visit(NodeId id, const mat4& worldFromParent, F& f) const {
    const Node& n = nodes_.at(id);
    const mat4 worldFromLocal = worldFromParent * n.parentFromLocal;
    f(id, worldFromLocal);
    for (NodeId c : n.children) visit(c, worldFromLocal, f);
  }

  uint32_t nextId_ = 1;  // shared by all entity types, never reused
  std::map<NodeId, Node> nodes_;
  std::map<MeshId, Mesh> meshes_;
  std::map<MaterialId, Material> materials_;
  std::map<TextureId, Texture> textures_;
  std::map<LightId, Light> lights_;
  std::map<CameraId, Camera> cameras_;
  std::vector<NodeId> roots_;
  Site site_;
  bool hasSite_ = false;
  SiteTime time_;
  SkySettings sky_;
  BakeSettings bake_;
  std::vector<Portal> portals_;
};

}  // namespace fly::sdb
