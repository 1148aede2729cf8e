// The node hierarchy (glTF nodes): transforms and what each node carries.
#pragma once

#include <string>
#include <vector>

#include "base/math.h"
#include "sdb/ids.h"

namespace fly::sdb {

struct Node {
  std::string name;
  NodeId parent;                  // 0 = a root node
  std::vector<NodeId> children;   // kept by Scene::addNode / removeNode
  mat4 parentFromLocal{1.0f};     // metres; may contain a negative scale (the importer fixes winding)
  std::vector<MeshId> meshes;
  CameraId camera;
  LightId light;
};

}  // namespace fly::sdb
