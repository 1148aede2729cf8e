#include "sdb/scene_load.h"

#include <algorithm>
#include <cctype>

#include "base/error.h"
#include "base/file_io.h"
#include "sdb/gltf_import.h"
#include "sdb/scene_file.h"

namespace fly::sdb {

Scene loadScene(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (ext == ".json") return loadSceneFile(path);
  if (ext == ".gltf" || ext == ".glb") {
    checkInputFile(path, "glTF file");
    Scene scene;
    scene.sourcePath = path;
    importGltf(scene, path);
    return scene;
  }
  checkInputFile(path, "scene");
  throw InputError({path.string()}, "unknown scene type '" + ext + "'",
                   "give a fly scene file (.json) or a glTF 2.0 model (.gltf or .glb)");
}

}  // namespace fly::sdb
