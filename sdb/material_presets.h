// Material presets for the classes architects and car designers use. Values and their sources are listed in
// material_presets.cpp and docs/scene-format.md.
#pragma once

#include <span>
#include <string>
#include <string_view>

#include "sdb/material.h"

namespace fly::sdb {

struct MaterialPreset {
  std::string_view name;         // scene-file key, e.g. "brushed-metal"
  std::string_view materialClass;  // coarse class reported by materialClass(), e.g. "metal"
  std::string_view description;  // what it is and where its values come from
  Material material;             // with name == preset == `name`
};

std::span<const MaterialPreset> materialPresets();

// nullptr when there is no preset of that name.
const MaterialPreset* findMaterialPreset(std::string_view name);

}  // namespace fly::sdb
