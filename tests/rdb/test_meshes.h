// Small SDB meshes for the RDB tests.
#pragma once

#include "sdb/mesh.h"

namespace fly::rdb::test {

// A unit quad in the local XZ plane (y = 0), counter-clockwise seen from +Y, normals +Y.
inline sdb::Mesh quadXZ(sdb::MaterialId material) {
  sdb::Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}};
  m.normals.assign(4, vec3(0, 1, 0));
  m.indices = {0, 2, 1, 0, 3, 2};
  m.material = material;
  return m;
}

// A unit quad in the local YZ plane (x = 0), counter-clockwise seen from +X, normals +X.
inline sdb::Mesh quadYZ(sdb::MaterialId material) {
  sdb::Mesh m;
  m.positions = {{0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1}};
  m.normals.assign(4, vec3(1, 0, 0));
  m.indices = {0, 1, 2, 0, 2, 3};
  m.material = material;
  return m;
}

}  // namespace fly::rdb::test
