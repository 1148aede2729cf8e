#include "cli/baked_light_maps.h"

#include <tiny_gltf.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

#include "base/error.h"
#include "base/file_io.h"
#include "cli/baked_scene.h"

namespace fly::cli {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr const char* kHintRebake =
    "the baked scene is damaged or incomplete: bake the scene again with fly bake";

// --- File access for tinygltf: a relative URI resolves in the glTF file's folder only (glTF 2.0, "URIs"),
// never in the current directory, and paths are taken as they are (no shell-style expansion).
struct FolderContext {
  std::string folder;  // ending in '/'
};

bool fileExists(const std::string& path, void* user) {
  const auto* ctx = static_cast<const FolderContext*>(user);
  std::error_code ec;
  return path.rfind(ctx->folder, 0) == 0 && fs::is_regular_file(path, ec);
}

std::string expandFilePath(const std::string& path, void*) {
  return path;
}

bool readWholeFile(std::vector<unsigned char>* out, std::string* err, const std::string& path, void*) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    *err = path + ": " + std::strerror(errno);
    return false;
  }
  out->assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  if (in.bad()) {
    *err = path + ": read error";
    return false;
  }
  return true;
}

tinygltf::Model loadSceneGltf(const fs::path& gltfPath) {
  const std::string text = readInputFile(gltfPath, "baked scene glTF");
  if (text.size() > std::numeric_limits<unsigned int>::max()) {
    throw InputError({gltfPath.string()}, "is larger than 4 GiB, which tinygltf cannot read", kHintRebake);
  }
  std::error_code ec;
  const fs::path folder = fs::absolute(gltfPath, ec).parent_path();
  FolderContext ctx{folder.string() + "/"};
  tinygltf::TinyGLTF loader;
  loader.SetFsCallbacks({&fileExists, &expandFilePath, &readWholeFile, nullptr, &ctx});
  tinygltf::Model model;
  std::string err, warn;
  if (!loader.LoadASCIIFromString(&model, &err, &warn, text.data(), static_cast<unsigned int>(text.size()),
                                  folder.string())) {
    // tinygltf's text names a buffer file it could not read or whose size is wrong ("File size mismatch").
    while (!err.empty() && (err.back() == '\n' || err.back() == ' ')) err.pop_back();
    throw InputError({gltfPath.string()}, "cannot be loaded: " + (err.empty() ? "not a glTF file" : err),
                     kHintRebake);
  }
  return model;
}

uint32_t manifestUint(const json& object, const char* key, const fs::path& manifestPath,
                      const std::string& at) {
  const auto it = object.find(key);
  if (it == object.end() || !it->is_number_unsigned() || it->get<uint64_t>() > UINT32_MAX) {
    throw InputError({manifestPath.string(), 0, 0, at + "/" + key},
                     std::string("needs \"") + key + "\", an integer in [0, 4294967295]", kHintRebake);
  }
  return it->get<uint32_t>();
}

// Reads the first `count` values of a VEC3 FLOAT accessor of `model`, checked against its buffer.
std::vector<Rgb> readIrradiance(const tinygltf::Model& model, int accessor, size_t count, const fs::path& dir,
                                const std::string& what) {
  const fs::path gltfPath = dir / "scene.gltf";
  const std::string path = "/accessors/" + std::to_string(accessor);
  if (accessor < 0 || size_t(accessor) >= model.accessors.size()) {
    throw InputError({gltfPath.string()}, what + " refers to a missing accessor " + std::to_string(accessor),
                     kHintRebake);
  }
  const tinygltf::Accessor& a = model.accessors[size_t(accessor)];
  if (a.type != TINYGLTF_TYPE_VEC3 || a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT || a.normalized ||
      a.sparse.isSparse) {
    throw InputError({gltfPath.string(), 0, 0, path}, what + " is not a plain VEC3 FLOAT accessor",
                     kHintRebake);
  }
  if (a.count < count) {
    throw InputError(
        {gltfPath.string(), 0, 0, path + "/count"},
        what + " has " + std::to_string(a.count) + " values, but manifest.json lists " +
            std::to_string(count) + " vertices",
        "manifest.json and scene.gltf are from different bakes: bake the scene again with fly bake");
  }
  if (a.bufferView < 0 || size_t(a.bufferView) >= model.bufferViews.size()) {
    throw InputError({gltfPath.string(), 0, 0, path + "/bufferView"}, what + " has no valid buffer view",
                     kHintRebake);
  }
  const tinygltf::BufferView& view = model.bufferViews[size_t(a.bufferView)];
  if (view.buffer < 0 || size_t(view.buffer) >= model.buffers.size()) {
    throw InputError({gltfPath.string(), 0, 0, "/bufferViews/" + std::to_string(a.bufferView)},
                     what + "'s buffer view refers to a missing buffer", kHintRebake);
  }
  const tinygltf::Buffer& buffer = model.buffers[size_t(view.buffer)];
  const fs::path bufferFile = buffer.uri.empty() ? gltfPath : dir / buffer.uri;
  const size_t element = 3 * sizeof(float);
  const size_t stride = view.byteStride == 0 ? element : view.byteStride;
  // Bytes the first `count` elements need, within the view and the view within the buffer; every size here
  // comes from a JSON number, so guard the arithmetic against overflow.
  const bool fitsView = count == 0 || (stride >= element && a.byteOffset <= view.byteLength &&
                                       view.byteLength - a.byteOffset >= element &&
                                       (count - 1) <= (view.byteLength - a.byteOffset - element) / stride);
  const bool viewFitsBuffer =
      view.byteOffset <= buffer.data.size() && view.byteLength <= buffer.data.size() - view.byteOffset;
  if (!viewFitsBuffer) {
    throw InputError({bufferFile.string()},
                     "is too short for buffer view " + std::to_string(a.bufferView) + " of scene.gltf",
                     kHintRebake);
  }
  if (!fitsView) {
    throw InputError({gltfPath.string(), 0, 0, path}, what + " does not fit in its buffer view", kHintRebake);
  }
  std::vector<Rgb> values(count);
  const unsigned char* base = buffer.data.data() + view.byteOffset + a.byteOffset;
  for (size_t v = 0; v < count; ++v) {
    std::memcpy(&values[v], base + v * stride, element);
    if (!isFinite(values[v])) {
      throw InputError(
          {bufferFile.string()},
          "holds a value that is not a finite number in " + what + ", vertex " + std::to_string(v),
          kHintRebake);
    }
  }
  return values;
}

}  // namespace

rdb::LightMapStore lightMapStoreFromBake(const rdb::TraceRdb& rdb, const raytracer::VertexLightMaps& maps) {
  const size_t n = rdb.positionsM.size();
  if (maps.frontLux.size() != n || maps.backLux.size() != n) {
    throw std::invalid_argument("lightMapStoreFromBake: the light maps do not have one value per vertex");
  }
  rdb::LightMapStore store;
  for (const rdb::TraceMesh& m : rdb.meshes) {
    if (m.triangleCount == 0) continue;
    rdb::MeshLightMap map;
    map.sdbNodeId = m.sdbNodeId;
    map.sdbMeshId = m.sdbMeshId;
    const auto first = maps.frontLux.begin() + m.firstVertex;
    map.frontLux.assign(first, first + m.vertexCount);
    if (m.twoSided) {
      const auto back = maps.backLux.begin() + m.firstVertex;
      map.backLux.assign(back, back + m.vertexCount);
    }
    store.meshes.push_back(std::move(map));
  }
  return store;
}

rdb::LightMapStore readBakedLightMaps(const fs::path& bakedDir) {
  const json manifest = readBakedManifest(bakedDir);
  const fs::path manifestPath = bakedDir / "manifest.json";
  const fs::path gltfPath = bakedDir / "scene.gltf";
  const auto objects = manifest.find("objects");
  if (objects == manifest.end() || !objects->is_array()) {
    throw InputError({manifestPath.string(), 0, 0, "/objects"}, "needs \"objects\", an array", kHintRebake);
  }
  const tinygltf::Model model = loadSceneGltf(gltfPath);

  rdb::LightMapStore store;
  for (size_t k = 0; k < objects->size(); ++k) {
    const json& o = (*objects)[k];
    const std::string at = "/objects/" + std::to_string(k);
    if (!o.is_object()) throw InputError({manifestPath.string(), 0, 0, at}, "is not an object", kHintRebake);
    const auto gltfMesh = o.find("gltf_mesh");
    if (gltfMesh == o.end() || gltfMesh->is_null()) continue;  // no triangles: nothing was written to draw
    const auto twoSided = o.find("two_sided");
    if (twoSided == o.end() || !twoSided->is_boolean()) {
      throw InputError({manifestPath.string(), 0, 0, at + "/two_sided"}, "needs \"two_sided\", true or false",
                       kHintRebake);
    }
    rdb::MeshLightMap map;
    map.sdbNodeId = manifestUint(o, "sdb_node_id", manifestPath, at);
    map.sdbMeshId = manifestUint(o, "sdb_mesh_id", manifestPath, at);
    const uint32_t vertices = manifestUint(o, "vertices", manifestPath, at);
    const uint32_t meshIndex = manifestUint(o, "gltf_mesh", manifestPath, at);
    if (meshIndex >= model.meshes.size()) {
      throw InputError(
          {manifestPath.string(), 0, 0, at + "/gltf_mesh"},
          "refers to glTF mesh " + std::to_string(meshIndex) + ", but scene.gltf has " +
              std::to_string(model.meshes.size()),
          "manifest.json and scene.gltf are from different bakes: bake the scene again with fly bake");
    }
    const tinygltf::Mesh& mesh = model.meshes[meshIndex];
    const std::string meshPath = "/meshes/" + std::to_string(meshIndex);
    if (mesh.primitives.empty()) {
      throw InputError({gltfPath.string(), 0, 0, meshPath}, "mesh has no primitives", kHintRebake);
    }
    // Every primitive of a baked mesh shares its vertex attributes; the first one's are the mesh's.
    const std::map<std::string, int>& attributes = mesh.primitives[0].attributes;
    for (const bool back : {false, true}) {
      if (back && !twoSided->get<bool>()) continue;
      const char* name = back ? "_IRRADIANCE_BACK" : "_IRRADIANCE_FRONT";
      const auto attribute = attributes.find(name);
      if (attribute == attributes.end()) {
        throw InputError({gltfPath.string(), 0, 0, meshPath + "/primitives/0/attributes"},
                         std::string("has no ") + name + " attribute" +
                             (back ? ", but manifest.json says the mesh is two-sided" : ""),
                         kHintRebake);
      }
      (back ? map.backLux : map.frontLux) = readIrradiance(
          model, attribute->second, vertices, bakedDir, "mesh " + std::to_string(meshIndex) + "'s " + name);
    }
    store.meshes.push_back(std::move(map));
  }
  return store;
}

}  // namespace fly::cli
