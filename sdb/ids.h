// Stable entity ids of the Scene Description Database. An id is never reused within a Scene, so RDB records
// can refer to SDB entities by id across edits.
#pragma once

#include <compare>
#include <cstdint>
#include <functional>

namespace fly::sdb {

template <class Tag>
struct Id {
  uint32_t value = 0;  // 0 = no entity

  explicit operator bool() const { return value != 0; }
  auto operator<=>(const Id&) const = default;
};

using NodeId = Id<struct NodeTag>;
using MeshId = Id<struct MeshTag>;
using MaterialId = Id<struct MaterialTag>;
using TextureId = Id<struct TextureTag>;
using LightId = Id<struct LightTag>;
using CameraId = Id<struct CameraTag>;

}  // namespace fly::sdb

template <class Tag>
struct std::hash<fly::sdb::Id<Tag>> {
  size_t operator()(const fly::sdb::Id<Tag>& id) const noexcept { return std::hash<uint32_t>()(id.value); }
};
