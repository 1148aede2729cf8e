// Loads any scene input fly accepts: a scene file (.json), or a glTF model (.gltf, .glb) on its own.
#pragma once

#include <filesystem>

#include "sdb/scene.h"

namespace fly::sdb {

// Chooses the reader by extension; anything else is an InputError that lists the accepted kinds.
Scene loadScene(const std::filesystem::path& path);

}  // namespace fly::sdb
