// What an SDB edit changed, so that RDBs update incrementally instead of rebuilding.
#pragma once

#include <cstdint>
#include <vector>

namespace fly::sdb {

enum class EntityType : uint8_t {
  kNode,
  kMesh,
  kMaterial,
  kTexture,
  kLight,
  kCamera,
  kSite,
  kTime,
  kSky,
  kBake,
  kPortals,  // the declared sky portals (sdb/portal.h), as a whole
};
enum class ChangeKind : uint8_t { kAdded, kModified, kRemoved };

// Which aspect of an entity changed; kAll when the whole entity was replaced, added or removed.
enum class Aspect : uint8_t {
  kAll,
  kTransform,   // a node's parentFromLocal (the world transforms of its subtree change)
  kHierarchy,   // a node's parent or children
  kAttachment,  // what a node carries (meshes, camera, light)
  kMaterialAssignment,  // a mesh's material
};

struct Change {
  EntityType type;
  uint32_t id;  // the entity's id value; 0 for scene-wide settings (site, time, sky, bake, portals)
  ChangeKind kind;
  Aspect aspect = Aspect::kAll;

  bool operator==(const Change&) const = default;
};

struct ChangeSet {
  std::vector<Change> changes;

  bool empty() const { return changes.empty(); }
  void add(Change c) { changes.push_back(c); }
  void merge(const ChangeSet& other) { changes.insert(changes.end(), other.changes.begin(), other.changes.end()); }
  // True when any change concerns entities of this type.
  bool touches(EntityType t) const {
    for (const Change& c : changes) {
      if (c.type == t) return true;
    }
    return false;
  }
};

}  // namespace fly::sdb
