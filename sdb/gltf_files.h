// File access for tinygltf, confined to one folder. tinygltf looks for a relative URI in the glTF file's folder
// and then in the current directory; glTF resolves URIs against the file's own location only (glTF 2.0,
// "URIs"), so files outside that folder's tree are reported as missing rather than silently taken from
// wherever the program runs, and paths are taken as they are (no shell-style expansion). Used by the glTF
// importer and by the reader of baked scene directories.
#pragma once

#include <filesystem>
#include <string>
#include <tiny_gltf.h>

namespace fly::sdb {

class GltfFolderFiles {
 public:
  // `folder`: the glTF file's folder, made absolute.
  explicit GltfFolderFiles(const std::filesystem::path& folder);

  // For tinygltf::TinyGLTF::SetFsCallbacks; valid while this object lives. No writing.
  tinygltf::FsCallbacks callbacks() const;

 private:
  std::string folder_;  // absolute, ending in '/'
};

}  // namespace fly::sdb
