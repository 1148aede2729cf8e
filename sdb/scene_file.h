// The fly scene file (JSON): places glTF models and adds what glTF lacks (site, time, sky, IES lights,
// material presets and overrides, bake settings, named cameras). docs/scene-format.md documents every key.
// Unknown keys and wrong types throw InputError naming the file, the line and column, the JSON path and the
// expected form.
#pragma once

#include <filesystem>
#include <string_view>

#include "sdb/scene.h"

namespace fly::sdb {

// Parses scene-file text; relative paths inside resolve against `baseDir`. `fileName` names it in errors.
Scene parseSceneFile(std::string_view text, const std::string& fileName, const std::filesystem::path& baseDir);

// Reads and parses a scene file.
Scene loadSceneFile(const std::filesystem::path& path);

}  // namespace fly::sdb
