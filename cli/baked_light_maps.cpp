#include "cli/baked_light_maps.h"

#include <tiny_gltf.h>

#include <algorithm>
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
#include "base/image_io.h"
#include "cli/baked_scene.h"
#include "sdb/gltf_files.h"

namespace fly::cli {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr const char* kHintRebake =
    "the baked scene is damaged or incomplete: bake the scene again with fly bake";

tinygltf::Model loadSceneGltf(const fs::path& gltfPath) {
  const std::string text = readInputFile(gltfPath, "baked scene glTF");
  if (text.size() > std::numeric_limits<unsigned int>::max()) {
    throw InputError({gltfPath.string()}, "is larger than 4 GiB, which tinygltf cannot read", kHintRebake);
  }
  std::error_code ec;
  const fs::path folder = fs::absolute(gltfPath, ec).parent_path();
  const sdb::GltfFolderFiles files(folder);
  tinygltf::TinyGLTF loader;
  loader.SetFsCallbacks(files.callbacks());
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

// The first `count` elements of an accessor of `model`, checked against its buffer: where they start and the
// bytes from one to the next. `type` and `componentType` are the only ones accepted (not normalised, not
// sparse); `typeName` names them in the message.
struct AccessorBytes {
  const unsigned char* base = nullptr;
  size_t stride = 0;
  fs::path bufferFile;  // the file that holds them, for messages
};
AccessorBytes checkedAccessor(const tinygltf::Model& model, int accessor, size_t count, int type,
                              int componentType, const char* typeName, const fs::path& dir,
                              const std::string& what) {
  const fs::path gltfPath = dir / "scene.gltf";
  const std::string path = "/accessors/" + std::to_string(accessor);
  if (accessor < 0 || size_t(accessor) >= model.accessors.size()) {
    throw InputError({gltfPath.string()}, what + " refers to a missing accessor " + std::to_string(accessor),
                     kHintRebake);
  }
  const tinygltf::Accessor& a = model.accessors[size_t(accessor)];
  if (a.type != type || a.componentType != componentType || a.normalized || a.sparse.isSparse) {
    throw InputError({gltfPath.string(), 0, 0, path}, what + " is not a plain " + typeName + " accessor",
                     kHintRebake);
  }
  if (a.count < count) {
    throw InputError(
        {gltfPath.string(), 0, 0, path + "/count"},
        what + " has " + std::to_string(a.count) + " values, but manifest.json lists " +
            std::to_string(count) + (type == TINYGLTF_TYPE_SCALAR ? "" : " vertices"),
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
  AccessorBytes r;
  r.bufferFile = buffer.uri.empty() ? gltfPath : dir / buffer.uri;
  const size_t element = size_t(tinygltf::GetComponentSizeInBytes(uint32_t(componentType))) *
                         size_t(tinygltf::GetNumComponentsInType(uint32_t(type)));
  r.stride = view.byteStride == 0 ? element : view.byteStride;
  // Bytes the first `count` elements need, within the view and the view within the buffer; every size here
  // comes from a JSON number, so guard the arithmetic against overflow.
  const bool fitsView = count == 0 || (r.stride >= element && a.byteOffset <= view.byteLength &&
                                       view.byteLength - a.byteOffset >= element &&
                                       (count - 1) <= (view.byteLength - a.byteOffset - element) / r.stride);
  const bool viewFitsBuffer =
      view.byteOffset <= buffer.data.size() && view.byteLength <= buffer.data.size() - view.byteOffset;
  if (!viewFitsBuffer) {
    throw InputError({r.bufferFile.string()},
                     "is too short for buffer view " + std::to_string(a.bufferView) + " of scene.gltf",
                     kHintRebake);
  }
  if (!fitsView) {
    throw InputError({gltfPath.string(), 0, 0, path}, what + " does not fit in its buffer view", kHintRebake);
  }
  r.base = buffer.data.data() + view.byteOffset + a.byteOffset;
  return r;
}

// Reads the first `count` values of a VEC3 FLOAT accessor of `model`, checked against its buffer.
std::vector<Rgb> readIrradiance(const tinygltf::Model& model, int accessor, size_t count, const fs::path& dir,
                                const std::string& what) {
  const AccessorBytes bytes = checkedAccessor(model, accessor, count, TINYGLTF_TYPE_VEC3,
                                              TINYGLTF_COMPONENT_TYPE_FLOAT, "VEC3 FLOAT", dir, what);
  std::vector<Rgb> values(count);
  for (size_t v = 0; v < count; ++v) {
    std::memcpy(&values[v], bytes.base + v * bytes.stride, sizeof(Rgb));
    if (!isFinite(values[v])) {
      throw InputError(
          {bytes.bufferFile.string()},
          "holds a value that is not a finite number in " + what + ", vertex " + std::to_string(v),
          kHintRebake);
    }
  }
  return values;
}

// The light-map UV of every triangle corner of a light-textured baked mesh: TEXCOORD_1 of the vertex each
// index of its primitives names (writeBakedScene: one primitive per material; an SDB mesh has one material,
// so the primitive's triangles are the mesh's triangles with area, in order). `triangles` is the manifest's
// count.
std::vector<vec2> readCornerUvs(const tinygltf::Model& model, uint32_t meshIndex, size_t triangles,
                                const fs::path& dir) {
  const fs::path gltfPath = dir / "scene.gltf";
  const tinygltf::Mesh& mesh = model.meshes[meshIndex];
  const std::string meshPath = "/meshes/" + std::to_string(meshIndex);
  const std::string what = "mesh " + std::to_string(meshIndex) + "'s TEXCOORD_1";
  const auto uvAttribute = mesh.primitives[0].attributes.find("TEXCOORD_1");
  if (uvAttribute == mesh.primitives[0].attributes.end()) {
    throw InputError({gltfPath.string(), 0, 0, meshPath + "/primitives/0/attributes"},
                     "has no TEXCOORD_1 attribute, but manifest.json gives the mesh a light texture",
                     kHintRebake);
  }
  const int uvAccessor = uvAttribute->second;
  const size_t uvCount = uvAccessor >= 0 && size_t(uvAccessor) < model.accessors.size()
                             ? model.accessors[size_t(uvAccessor)].count
                             : 0;
  const AccessorBytes uvBytes = checkedAccessor(model, uvAccessor, uvCount, TINYGLTF_TYPE_VEC2,
                                                TINYGLTF_COMPONENT_TYPE_FLOAT, "VEC2 FLOAT", dir, what);
  std::vector<vec2> corners;
  for (size_t k = 0; k < mesh.primitives.size(); ++k) {
    const tinygltf::Primitive& primitive = mesh.primitives[k];
    const std::string primitivePath = meshPath + "/primitives/" + std::to_string(k);
    if (primitive.mode != TINYGLTF_MODE_TRIANGLES || primitive.indices < 0 ||
        size_t(primitive.indices) >= model.accessors.size()) {
      throw InputError({gltfPath.string(), 0, 0, primitivePath}, "is not an indexed triangle list",
                       kHintRebake);
    }
    const size_t count = model.accessors[size_t(primitive.indices)].count;
    const std::string indicesWhat = "mesh " + std::to_string(meshIndex) + "'s indices";
    const AccessorBytes indexBytes =
        checkedAccessor(model, primitive.indices, count, TINYGLTF_TYPE_SCALAR,
                        TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, "SCALAR UNSIGNED_INT", dir, indicesWhat);
    for (size_t c = 0; c < count; ++c) {
      uint32_t vertex = 0;
      std::memcpy(&vertex, indexBytes.base + c * indexBytes.stride, sizeof vertex);
      if (vertex >= uvCount) {
        throw InputError({gltfPath.string(), 0, 0, primitivePath + "/indices"},
                         "index " + std::to_string(vertex) + " is beyond the mesh's " +
                             std::to_string(uvCount) + " vertices",
                         kHintRebake);
      }
      vec2 uv;
      std::memcpy(&uv, uvBytes.base + vertex * uvBytes.stride, sizeof uv);
      if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) {
        throw InputError(
            {uvBytes.bufferFile.string()},
            "holds a value that is not a finite number in " + what + ", vertex " + std::to_string(vertex),
            kHintRebake);
      }
      corners.push_back(uv);
    }
  }
  if (corners.size() != 3 * triangles) {
    throw InputError(
        {gltfPath.string(), 0, 0, meshPath},
        "has " + std::to_string(corners.size()) + " triangle corners, but manifest.json lists " +
            std::to_string(triangles) + " triangles",
        "manifest.json and scene.gltf are from different bakes: bake the scene again with fly bake");
  }
  return corners;
}

// One side of a light texture: the EXR file `relative` (manifest.json's entry at `at`) of width × height
// texels, finite (readExr checks), as Rgb values row-major from the top row.
std::vector<Rgb> readLightTextureSide(const fs::path& dir, const json& entry, const char* side,
                                      uint32_t width, uint32_t height, const std::string& at) {
  const fs::path manifestPath = dir / "manifest.json";
  const auto file = entry.find(side);
  if (file == entry.end() || !file->is_string() || file->get<std::string>().empty()) {
    throw InputError({manifestPath.string(), 0, 0, at + "/" + side},
                     std::string("needs \"") + side + "\", the path of the light texture's EXR file",
                     kHintRebake);
  }
  const fs::path relative = file->get<std::string>();
  if (relative.is_absolute() ||
      std::any_of(relative.begin(), relative.end(), [](const fs::path& part) { return part == ".."; })) {
    throw InputError({manifestPath.string(), 0, 0, at + "/" + side},
                     "names " + relative.string() + ", which is outside the baked directory", kHintRebake);
  }
  const fs::path path = dir / relative;
  const ImageRgbF image = readExr(path);  // InputError naming the file: missing, corrupt, NaN or Inf
  if (image.width != int(width) || image.height != int(height)) {
    throw InputError({path.string()},
                     "is " + std::to_string(image.width) + "×" + std::to_string(image.height) +
                         " texels, but manifest.json gives the light texture " + std::to_string(width) + "×" +
                         std::to_string(height),
                     kHintRebake);
  }
  std::vector<Rgb> texels(size_t(width) * height);
  std::memcpy(texels.data(), image.rgb.data(), texels.size() * sizeof(Rgb));
  return texels;
}

// The manifest's "sun_direct" (cli/baked_scene.h): the bake's sun direction, a finite unit vector, and its
// normal illuminance, finite and ≥ 0.
rdb::BakedSun readBakedSun(const json& entry, const fs::path& manifestPath) {
  auto vector = [&](const char* key, bool unit) {
    const auto v = entry.is_object() ? entry.find(key) : entry.end();
    bool ok = entry.is_object() && v != entry.end() && v->is_array() && v->size() == 3 &&
              std::all_of(v->begin(), v->end(), [](const json& x) { return x.is_number(); });
    vec3 r(0.0f);
    if (ok) {
      r = vec3((*v)[0].get<float>(), (*v)[1].get<float>(), (*v)[2].get<float>());
      ok = isFinite(r) &&
           (unit ? std::abs(glm::length(r) - 1.0f) < 1e-3f : glm::all(glm::greaterThanEqual(r, vec3(0.0f))));
    }
    if (!ok) {
      throw InputError({manifestPath.string(), 0, 0, std::string("/sun_direct/") + key},
                       std::string("needs \"") + key + "\", " +
                           (unit ? "a unit vector [x, y, z]" : "three finite numbers ≥ 0 (lux)"),
                       kHintRebake);
    }
    return r;
  };
  rdb::BakedSun sun;
  sun.directionWorld = vector("direction_world", true);
  sun.normalIlluminanceLux = vector("normal_illuminance_lux", false);
  return sun;
}

}  // namespace

namespace {

void foldSpread(std::vector<Rgb>& stdErrorLux, const std::vector<Rgb>& spreadLux) {
  if (spreadLux.size() != stdErrorLux.size()) return;
  for (size_t i = 0; i < stdErrorLux.size(); ++i)
    stdErrorLux[i] = glm::sqrt(stdErrorLux[i] * stdErrorLux[i] + spreadLux[i] * spreadLux[i]);
}

}  // namespace

raytracer::VertexLightMaps withPointReadErrors(const raytracer::VertexLightMaps& baked) {
  raytracer::VertexLightMaps maps = baked;
  foldSpread(maps.frontStdErrorLux, maps.frontSunDirectSpreadLux);
  foldSpread(maps.backStdErrorLux, maps.backSunDirectSpreadLux);
  for (raytracer::LightTexture& tex : maps.lightTextures) {
    foldSpread(tex.frontStdErrorLux, tex.frontSunDirectSpreadLux);
    foldSpread(tex.backStdErrorLux, tex.backSunDirectSpreadLux);
  }
  return maps;
}

rdb::LightMapStore lightMapStoreFromBake(const rdb::TraceRdb& rdb, const raytracer::VertexLightMaps& bakedMaps) {
  const raytracer::VertexLightMaps maps = withPointReadErrors(bakedMaps);
  const size_t n = rdb.positionsM.size();
  if (maps.frontLux.size() != n || maps.backLux.size() != n || maps.frontStdErrorLux.size() != n ||
      maps.backStdErrorLux.size() != n) {
    throw std::invalid_argument("lightMapStoreFromBake: the light maps do not have one value per vertex");
  }
  const bool sun = maps.hasSunDirect();
  if (sun && (maps.frontSunDirectLux.size() != n || maps.backSunDirectLux.size() != n)) {
    throw std::invalid_argument(
        "lightMapStoreFromBake: the sun-direct maps do not have one value per vertex");
  }
  rdb::LightMapStore store;
  if (sun) store.sun = rdb::BakedSun{rdb.sun.directionWorld, rdb.sun.normalIlluminanceLux};
  auto vertices = [](const std::vector<Rgb>& all, const rdb::TraceMesh& m) {
    const auto first = all.begin() + m.firstVertex;
    return std::vector<Rgb>(first, first + m.vertexCount);
  };
  for (const rdb::TraceMesh& m : rdb.meshes) {
    if (m.triangleCount == 0) continue;
    rdb::MeshLightMap map;
    map.sdbNodeId = m.sdbNodeId;
    map.sdbMeshId = m.sdbMeshId;
    map.frontLux = vertices(maps.frontLux, m);
    if (m.twoSided) map.backLux = vertices(maps.backLux, m);
    map.frontStdErrorLux = vertices(maps.frontStdErrorLux, m);
    if (m.twoSided) map.backStdErrorLux = vertices(maps.backStdErrorLux, m);
    if (sun) {
      map.frontSunDirectLux = vertices(maps.frontSunDirectLux, m);
      if (m.twoSided) map.backSunDirectLux = vertices(maps.backSunDirectLux, m);
    }
    if (m.lightTexture != rdb::TraceMesh::kNoLightTexture) {
      const rdb::TraceLightTexture& lt = rdb.lightTextures.at(m.lightTexture);
      const raytracer::LightTexture& baked = maps.lightTextures.at(m.lightTexture);
      if (baked.width != lt.width || baked.height != lt.height ||
          baked.frontLux.size() != size_t(lt.width) * lt.height ||
          lt.cornerUv.size() != 3 * size_t(m.triangleCount)) {
        throw std::invalid_argument("lightMapStoreFromBake: a light texture does not match its mesh");
      }
      rdb::MeshLightTexture t;
      t.width = lt.width;
      t.height = lt.height;
      t.frontLux = baked.frontLux;
      t.frontStdErrorLux = baked.frontStdErrorLux;
      if (m.twoSided) {
        t.backLux = baked.backLux;
        t.backStdErrorLux = baked.backStdErrorLux;
      }
      if (sun) {
        t.frontSunDirectLux = baked.frontSunDirectLux;
        if (m.twoSided) t.backSunDirectLux = baked.backSunDirectLux;
      }
      t.cornerUv = lt.cornerUv;
      map.lightTexture = std::move(t);
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
  // "sun_direct": the bake kept the sun's direct light apart (absent or null in bakes that did not).
  const auto sunDirect = manifest.find("sun_direct");
  const bool sun = sunDirect != manifest.end() && !sunDirect->is_null();
  if (sun) store.sun = readBakedSun(*sunDirect, manifestPath);
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
    // The irradiance, its standard error (kept for the viewer's lux probe) and the sun-direct part.
    enum class Part { kIrradiance, kStdError, kSunDirect };
    for (const Part part : {Part::kIrradiance, Part::kStdError, Part::kSunDirect}) {
      const bool sunPart = part == Part::kSunDirect;
      if (sunPart && !sun) continue;
      for (const bool back : {false, true}) {
        if (back && !twoSided->get<bool>()) continue;
        const char* name = sunPart ? (back ? "_SUN_DIRECT_BACK" : "_SUN_DIRECT_FRONT")
                           : part == Part::kStdError
                               ? (back ? "_IRRADIANCE_BACK_STDERR" : "_IRRADIANCE_FRONT_STDERR")
                               : (back ? "_IRRADIANCE_BACK" : "_IRRADIANCE_FRONT");
        const auto attribute = attributes.find(name);
        if (attribute == attributes.end()) {
          throw InputError({gltfPath.string(), 0, 0, meshPath + "/primitives/0/attributes"},
                           std::string("has no ") + name + " attribute" +
                               (back ? ", but manifest.json says the mesh is two-sided"
                                     : (sunPart ? ", but manifest.json gives the bake a sun_direct" : "")),
                           kHintRebake);
        }
        std::vector<Rgb>& into = sunPart ? (back ? map.backSunDirectLux : map.frontSunDirectLux)
                                 : part == Part::kStdError
                                     ? (back ? map.backStdErrorLux : map.frontStdErrorLux)
                                     : (back ? map.backLux : map.frontLux);
        into = readIrradiance(model, attribute->second, vertices, bakedDir,
                              "mesh " + std::to_string(meshIndex) + "'s " + name);
      }
    }
    const auto texture = o.find("light_texture");
    if (texture != o.end()) {
      const std::string textureAt = at + "/light_texture";
      if (!texture->is_object()) {
        throw InputError({manifestPath.string(), 0, 0, textureAt}, "is not an object", kHintRebake);
      }
      rdb::MeshLightTexture t;
      t.width = manifestUint(*texture, "width", manifestPath, textureAt);
      t.height = manifestUint(*texture, "height", manifestPath, textureAt);
      if (t.width < 1 || t.height < 1 || uint64_t(t.width) * t.height > (uint64_t(1) << 28)) {
        throw InputError({manifestPath.string(), 0, 0, textureAt},
                         "gives the light texture " + std::to_string(t.width) + "×" +
                             std::to_string(t.height) +
                             " texels (each side must be ≥ 1, at most 2^28 texels in all)",
                         kHintRebake);
      }
      t.frontLux = readLightTextureSide(bakedDir, *texture, "front", t.width, t.height, textureAt);
      t.frontStdErrorLux =
          readLightTextureSide(bakedDir, *texture, "front_stderr", t.width, t.height, textureAt);
      if (twoSided->get<bool>()) {
        t.backLux = readLightTextureSide(bakedDir, *texture, "back", t.width, t.height, textureAt);
        t.backStdErrorLux =
            readLightTextureSide(bakedDir, *texture, "back_stderr", t.width, t.height, textureAt);
      }
      if (sun) {
        t.frontSunDirectLux =
            readLightTextureSide(bakedDir, *texture, "front_sun_direct", t.width, t.height, textureAt);
        if (twoSided->get<bool>()) {
          t.backSunDirectLux =
              readLightTextureSide(bakedDir, *texture, "back_sun_direct", t.width, t.height, textureAt);
        }
      }
      t.cornerUv = readCornerUvs(model, meshIndex, manifestUint(o, "triangles", manifestPath, at), bakedDir);
      map.lightTexture = std::move(t);
    }
    store.meshes.push_back(std::move(map));
  }
  return store;
}

}  // namespace fly::cli
