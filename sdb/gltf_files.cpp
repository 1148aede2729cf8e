#include "sdb/gltf_files.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>
#include <system_error>
#include <vector>

namespace fly::sdb {
namespace {

bool fileExists(const std::string& path, void* user) {
  const auto* folder = static_cast<const std::string*>(user);
  std::error_code ec;
  return path.rfind(*folder, 0) == 0 && std::filesystem::is_regular_file(path, ec);
}

std::string expandFilePath(const std::string& path, void*) {
  return path;
}

bool readWholeFile(std::vector<unsigned char>* out, std::string* err, const std::string& path, void*) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    *err = std::strerror(errno);
    return false;
  }
  out->assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  if (in.bad()) {
    *err = "read error";
    return false;
  }
  return true;
}

}  // namespace

GltfFolderFiles::GltfFolderFiles(const std::filesystem::path& folder) {
  std::error_code ec;
  folder_ = std::filesystem::absolute(folder, ec).string() + "/";
}

tinygltf::FsCallbacks GltfFolderFiles::callbacks() const {
  return {&fileExists, &expandFilePath, &readWholeFile, nullptr, const_cast<std::string*>(&folder_)};
}

}  // namespace fly::sdb
