#include "cli/baked_scene.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <optional>
#include <random>
#include <span>
#include <stdexcept>

#include "base/error.h"
#include "base/file_io.h"
#include "base/image_io.h"
#include "base/math.h"
#include "base/tone_map.h"
#include "cli/baked_light_maps.h"
#include "cli/command.h"
#include "cli/convergence_plot.h"
#include "cli/image_metadata.h"

namespace fly::cli {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// glTF 2.0 enumerations (§5.1.3 componentType, §5.11.1 bufferView target).
constexpr int kFloat = 5126;
constexpr int kUnsignedInt = 5125;
constexpr int kArrayBuffer = 34962;
constexpr int kElementArrayBuffer = 34963;

// A glTF document with one binary buffer, built accessor by accessor. Every view starts 4-byte aligned (all
// data here is 4-byte floats and integers).
class GltfBuilder {
 public:
  // A VEC3 FLOAT accessor over `v`; `bounds` adds min and max (required for POSITION).
  int vec3s(std::span<const vec3> v, bool bounds = false) {
    json a = accessor(v.data(), v.size_bytes(), kArrayBuffer, kFloat, v.size(), "VEC3");
    if (bounds && !v.empty()) {
      vec3 lo = v[0], hi = v[0];
      for (const vec3& p : v) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
      }
      a["min"] = {lo.x, lo.y, lo.z};
      a["max"] = {hi.x, hi.y, hi.z};
    }
    return push(std::move(a));
  }
  int vec2s(std::span<const vec2> v) {
    return push(accessor(v.data(), v.size_bytes(), kArrayBuffer, kFloat, v.size(), "VEC2"));
  }
  int floats(std::span<const float> v) {
    return push(accessor(v.data(), v.size_bytes(), kArrayBuffer, kFloat, v.size(), "SCALAR"));
  }
  int indices(std::span<const uint32_t> v) {
    return push(accessor(v.data(), v.size_bytes(), kElementArrayBuffer, kUnsignedInt, v.size(), "SCALAR"));
  }

  // The document with its buffer named `binName`, and the buffer's bytes.
  json finish(json doc, const std::string& binName) {
    doc["asset"] = {{"version", "2.0"}, {"generator", std::string("fly ") + kFlyVersion}};
    doc["buffers"] = json::array({{{"uri", binName}, {"byteLength", bin_.size()}}});
    doc["bufferViews"] = std::move(views_);
    doc["accessors"] = std::move(accessors_);
    return doc;
  }
  const std::string& bin() const { return bin_; }

 private:
  json accessor(const void* data, size_t bytes, int target, int componentType, size_t count,
                const char* type) {
    views_.push_back({{"buffer", 0}, {"byteOffset", bin_.size()}, {"byteLength", bytes}, {"target", target}});
    bin_.append(static_cast<const char*>(data), bytes);
    return {{"bufferView", views_.size() - 1},
            {"componentType", componentType},
            {"count", count},
            {"type", type}};
  }
  int push(json a) {
    accessors_.push_back(std::move(a));
    return static_cast<int>(accessors_.size() - 1);
  }

  json views_ = json::array();
  json accessors_ = json::array();
  std::string bin_;
};

// The triangles of a mesh grouped by material, in the order the materials are first met: one primitive each.
struct MaterialGroup {
  uint32_t material = 0;
  std::vector<uint32_t> indices;  // relative to the mesh's firstVertex
};
// cornerVertex (3 per triangle of the mesh), when given, replaces the TraceRdb's indices (seam-split
// vertices).
std::vector<MaterialGroup> groupByMaterial(const rdb::TraceRdb& rdb, const rdb::TraceMesh& m,
                                           const std::vector<uint32_t>* cornerVertex = nullptr) {
  std::vector<MaterialGroup> groups;
  for (uint32_t t = m.firstTriangle; t < m.firstTriangle + m.triangleCount; ++t) {
    const uint32_t material = rdb.triangleMaterial[t];
    auto g = std::find_if(groups.begin(), groups.end(),
                          [&](const MaterialGroup& x) { return x.material == material; });
    if (g == groups.end()) g = groups.insert(groups.end(), {material, {}});
    for (size_t k = 0; k < 3; ++k) {
      g->indices.push_back(cornerVertex ? (*cornerVertex)[3 * size_t(t - m.firstTriangle) + k]
                                        : rdb.indices[3 * size_t(t) + k] - m.firstVertex);
    }
  }
  return groups;
}

// A light-textured mesh's vertices split where charts meet: the mesh's vertices first (each with the UV of
// its first corner in triangle order; (0, 0) for a vertex of no triangle), then a copy for every further
// (vertex, UV) pair. All relative to the mesh's firstVertex.
struct SeamSplit {
  std::vector<uint32_t> sourceVertex;  // per output vertex
  std::vector<vec2> uv1;               // per output vertex
  std::vector<uint32_t> cornerVertex;  // per triangle corner: its output vertex
};
SeamSplit splitAtSeams(const rdb::TraceRdb& rdb, const rdb::TraceMesh& m, const rdb::TraceLightTexture& lt) {
  SeamSplit s;
  for (uint32_t v = 0; v < m.vertexCount; ++v) s.sourceVertex.push_back(v);
  s.uv1.assign(m.vertexCount, vec2(0.0f));
  std::vector<bool> assigned(m.vertexCount, false);
  std::vector<std::vector<uint32_t>> copies(m.vertexCount);  // output vertices of each source vertex
  for (size_t c = 0; c < 3 * size_t(m.triangleCount); ++c) {
    const uint32_t v = rdb.indices[3 * size_t(m.firstTriangle) + c] - m.firstVertex;
    const vec2 uv = lt.cornerUv[c];
    if (!assigned[v]) {
      assigned[v] = true;
      s.uv1[v] = uv;
      copies[v].push_back(v);
      s.cornerVertex.push_back(v);
      continue;
    }
    auto same = std::find_if(copies[v].begin(), copies[v].end(), [&](uint32_t o) { return s.uv1[o] == uv; });
    if (same == copies[v].end()) {
      same = copies[v].insert(copies[v].end(), uint32_t(s.sourceVertex.size()));
      s.sourceVertex.push_back(v);
      s.uv1.push_back(uv);
    }
    s.cornerVertex.push_back(*same);
  }
  return s;
}

// The per-vertex values of a mesh, gathered for the output vertices of a seam split (or as they are).
std::vector<vec3> gather(std::span<const vec3> values, const SeamSplit* split) {
  if (!split) return {values.begin(), values.end()};
  std::vector<vec3> out;
  for (uint32_t v : split->sourceVertex) out.push_back(values[v]);
  return out;
}

// Files of one light texture, relative to the baked directory: lightmaps/objectN_SIDE[_sun][_stderr].exr
// (_sun: the sun-direct part).
std::string lightTextureFile(size_t object, bool back, bool stdError, const char* extension = ".exr",
                             bool sunDirect = false) {
  return "lightmaps/object" + std::to_string(object) + (back ? "_back" : "_front") +
         (sunDirect ? "_sun" : "") + (stdError ? "_stderr" : "") + extension;
}

json lightTextureFilesJson(size_t object, bool twoSided, bool sunDirect) {
  json j = {{"front", lightTextureFile(object, false, false)},
            {"front_stderr", lightTextureFile(object, false, true)}};
  if (twoSided) {
    j["back"] = lightTextureFile(object, true, false);
    j["back_stderr"] = lightTextureFile(object, true, true);
  }
  if (sunDirect) {
    j["front_sun_direct"] = lightTextureFile(object, false, false, ".exr", true);
    j["front_sun_direct_stderr"] = lightTextureFile(object, false, true, ".exr", true);
    if (twoSided) {
      j["back_sun_direct"] = lightTextureFile(object, true, false, ".exr", true);
      j["back_sun_direct_stderr"] = lightTextureFile(object, true, true, ".exr", true);
    }
  }
  return j;
}

std::span<const vec3> range(const std::vector<vec3>& v, const rdb::TraceMesh& m) {
  return std::span<const vec3>(v).subspan(m.firstVertex, m.vertexCount);
}

json materialJson(const rdb::TraceMaterial& m, const std::string& name) {
  json j = {{"pbrMetallicRoughness",
             {{"baseColorFactor", {m.diffuse.r, m.diffuse.g, m.diffuse.b, 1.0f}},
              {"metallicFactor", 0.0f},
              {"roughnessFactor", 1.0f}}},
            {"doubleSided", m.doubleSided}};
  if (!name.empty()) j["name"] = name;
  return j;
}

// One glTF node per baked mesh, all at the root with identity transforms: the geometry is in world space.
void nodesAndScene(json& doc, const std::vector<json>& nodes) {
  doc["nodes"] = nodes;
  json roots = json::array();
  for (size_t i = 0; i < nodes.size(); ++i) roots.push_back(i);
  doc["scenes"] = json::array({{{"nodes", roots}}});
  doc["scene"] = 0;
}

json node(const BakeDescription& d, size_t meshIndex, size_t gltfMesh) {
  json n = {{"mesh", gltfMesh}};
  if (!d.nodeNames[meshIndex].empty()) n["name"] = d.nodeNames[meshIndex];
  return n;
}

json meshJson(const BakeDescription& d, size_t meshIndex, json primitives) {
  json mesh = {{"primitives", std::move(primitives)}};
  if (!d.meshNames[meshIndex].empty()) mesh["name"] = d.meshNames[meshIndex];
  return mesh;
}

// scene.gltf + scene.bin: the geometry with its float light maps. Meshes whose every triangle was degenerate
// have no primitive to draw (glTF requires at least one) and are left out; the manifest still lists them.
void writeBakedGltf(const fs::path& dir, const rdb::TraceRdb& rdb, const raytracer::VertexLightMaps& maps,
                    const BakeDescription& d) {
  GltfBuilder b;
  json doc;
  json meshes = json::array();
  std::vector<json> nodes;
  for (size_t i = 0; i < rdb.meshes.size(); ++i) {
    const rdb::TraceMesh& m = rdb.meshes[i];
    std::optional<SeamSplit> split;
    if (m.lightTexture != rdb::TraceMesh::kNoLightTexture) {
      split = splitAtSeams(rdb, m, rdb.lightTextures[m.lightTexture]);
    }
    const SeamSplit* sp = split ? &*split : nullptr;
    const std::vector<MaterialGroup> groups = groupByMaterial(rdb, m, sp ? &sp->cornerVertex : nullptr);
    if (groups.empty()) continue;
    json attributes = {{"POSITION", b.vec3s(gather(range(rdb.positionsM, m), sp), true)},
                       {"NORMAL", b.vec3s(gather(range(rdb.normals, m), sp))},
                       {"_IRRADIANCE_FRONT", b.vec3s(gather(range(maps.frontLux, m), sp))},
                       {"_IRRADIANCE_FRONT_STDERR", b.vec3s(gather(range(maps.frontStdErrorLux, m), sp))}};
    if (m.twoSided) {
      attributes["_IRRADIANCE_BACK"] = b.vec3s(gather(range(maps.backLux, m), sp));
      attributes["_IRRADIANCE_BACK_STDERR"] = b.vec3s(gather(range(maps.backStdErrorLux, m), sp));
    }
    if (maps.hasSunDirect()) {
      attributes["_SUN_DIRECT_FRONT"] = b.vec3s(gather(range(maps.frontSunDirectLux, m), sp));
      attributes["_SUN_DIRECT_FRONT_STDERR"] = b.vec3s(gather(range(maps.frontSunDirectStdErrorLux, m), sp));
      if (m.twoSided) {
        attributes["_SUN_DIRECT_BACK"] = b.vec3s(gather(range(maps.backSunDirectLux, m), sp));
        attributes["_SUN_DIRECT_BACK_STDERR"] = b.vec3s(gather(range(maps.backSunDirectStdErrorLux, m), sp));
      }
    }
    if (sp) {
      attributes["TEXCOORD_1"] = b.vec2s(sp->uv1);
      const std::vector<float> source(sp->sourceVertex.begin(), sp->sourceVertex.end());
      attributes["_SOURCE_VERTEX"] = b.floats(source);
    }
    json primitives = json::array();
    for (const MaterialGroup& g : groups) {
      primitives.push_back(
          {{"attributes", attributes}, {"indices", b.indices(g.indices)}, {"material", g.material}});
    }
    json mesh = meshJson(d, i, std::move(primitives));
    if (sp) {
      const rdb::TraceLightTexture& lt = rdb.lightTextures[m.lightTexture];
      json files = lightTextureFilesJson(i, m.twoSided, maps.hasSunDirect());
      files["width"] = lt.width;
      files["height"] = lt.height;
      files["texels_per_metre"] = lt.texelsPerMetre;
      mesh["extras"] = {{"fly", {{"light_texture", std::move(files)}}}};
    }
    meshes.push_back(std::move(mesh));
    nodes.push_back(node(d, i, meshes.size() - 1));
  }
  json materials = json::array();
  for (size_t k = 0; k < rdb.materials.size(); ++k)
    materials.push_back(materialJson(rdb.materials[k], d.materialNames[k]));
  doc["meshes"] = std::move(meshes);
  doc["materials"] = std::move(materials);
  nodesAndScene(doc, nodes);
  doc = b.finish(std::move(doc), "scene.bin");
  writeFileAtomic(dir / "scene.bin", b.bin());
  writeFileAtomic(dir / "scene.gltf", doc.dump(1) + "\n");
}

// export/scene.gltf + scene.bin for any glTF viewer. COLOR_0 is the displayed colour of the luminance
// L = albedo·E/π + emission (cd/m²) under automatic exposure and Reinhard's operator. toneMap's result is a
// linear display value, which is what glTF's COLOR_0 holds (linear; the viewer encodes to sRGB on output),
// so no transfer function is applied here. The material is unlit with a white base colour, so the viewer
// shows COLOR_0 as is. A vertex shared by triangles of different materials has one colour per material: one
// COLOR_0 accessor per primitive. Two-sided meshes get a second primitive per material for the back: normals
// negated, winding reversed, the back's light.
std::vector<std::string> writeExportGltf(const fs::path& dir, const rdb::TraceRdb& rdb,
                                         const raytracer::VertexLightMaps& maps, const BakeDescription& d) {
  struct Side {
    size_t mesh;
    const MaterialGroup* group;
    bool back;
    std::vector<Rgb> luminanceCdM2;
  };
  std::vector<std::vector<MaterialGroup>> groups;
  std::vector<Side> sides;
  for (size_t i = 0; i < rdb.meshes.size(); ++i) groups.push_back(groupByMaterial(rdb, rdb.meshes[i]));
  std::vector<float> allLuminances;
  for (size_t i = 0; i < rdb.meshes.size(); ++i) {
    const rdb::TraceMesh& m = rdb.meshes[i];
    for (const MaterialGroup& g : groups[i]) {
      const rdb::TraceMaterial& material = rdb.materials[g.material];
      for (const bool back : {false, true}) {
        if (back && !m.twoSided) continue;
        const std::span<const vec3> e = range(back ? maps.backLux : maps.frontLux, m);
        const Rgb emission = !back || material.doubleSided ? material.emissionCdM2 : Rgb(0.0f);
        Side s{i, &g, back, {}};
        for (const vec3& lux : e) {
          s.luminanceCdM2.push_back(material.diffuse * lux / kPiF + emission);
          allLuminances.push_back(luminance(s.luminanceCdM2.back()));
        }
        sides.push_back(std::move(s));
      }
    }
  }
  const double ev100 = autoExposureEv100(allLuminances);
  // The export's light-texture PNGs are textures (no print resolution): the daylight and the exposure.
  ImageSettings exportSettings = d.imageSettings;
  char exposure[64];
  std::snprintf(exposure, sizeof exposure, "EV100 %.2f (auto), tone operator reinhard", ev100);
  exportSettings.emplace_back("fly:exposure", exposure);
  fs::create_directory(dir);

  GltfBuilder b;
  json doc;
  json meshes = json::array();
  std::vector<json> nodes;
  size_t next = 0;
  json materials = json::array();
  for (size_t k = 0; k < rdb.materials.size(); ++k) {
    json material = {{"pbrMetallicRoughness", {{"baseColorFactor", {1.0, 1.0, 1.0, 1.0}}}},
                     {"extensions", {{"KHR_materials_unlit", json::object()}}}};
    if (!d.materialNames[k].empty()) material["name"] = d.materialNames[k];
    materials.push_back(std::move(material));
  }
  json images = json::array();
  std::vector<std::string> pngs;
  for (size_t i = 0; i < rdb.meshes.size(); ++i) {
    if (groups[i].empty()) continue;
    const rdb::TraceMesh& m = rdb.meshes[i];
    std::optional<SeamSplit> split;
    if (m.lightTexture != rdb::TraceMesh::kNoLightTexture) {
      split = splitAtSeams(rdb, m, rdb.lightTextures[m.lightTexture]);
    }
    const SeamSplit* sp = split ? &*split : nullptr;
    const std::vector<vec3> normals = gather(range(rdb.normals, m), sp);
    const int position = b.vec3s(gather(range(rdb.positionsM, m), sp), true);
    const int normal = b.vec3s(normals);
    int backNormal = -1;
    if (m.twoSided) {
      std::vector<vec3> negated;
      for (const vec3& n : normals) negated.push_back(-n);
      backNormal = b.vec3s(negated);
    }
    // A light-textured mesh: per side one PNG light map and one unlit material that shows it through
    // TEXCOORD_1, instead of vertex colours.
    int texcoord = -1;
    int textureMaterial[2] = {-1, -1};
    std::vector<MaterialGroup> splitGroups;
    if (sp) {
      texcoord = b.vec2s(sp->uv1);
      splitGroups = groupByMaterial(rdb, m, &sp->cornerVertex);
      const raytracer::LightTexture& tex = maps.lightTextures.at(m.lightTexture);
      const rdb::TraceMaterial& material = rdb.materials[rdb.triangleMaterial[m.firstTriangle]];
      for (const bool back : {false, true}) {
        if (back && !m.twoSided) continue;
        const std::vector<Rgb>& lux = back ? tex.backLux : tex.frontLux;
        const Rgb emission = !back || material.doubleSided ? material.emissionCdM2 : Rgb(0.0f);
        std::vector<float> rgb;
        for (const Rgb& e : lux) {
          const Rgb l = material.diffuse * e / kPiF + emission;
          rgb.insert(rgb.end(), {l.r, l.g, l.b});
        }
        const std::string file = lightTextureFile(i, back, false, ".png");
        fs::create_directories(dir / "lightmaps");
        writePng(dir / file, int(tex.width), int(tex.height), 3,
                 toneMapToSrgb8(rgb, ev100, ToneOperator::kReinhard).data(),
                 imageMetadata("Light texture for glTF viewers: tone-mapped albedo · E / π + emission",
                               exportSettings));
        pngs.push_back(file);
        images.push_back({{"uri", file}});
        textureMaterial[back] = int(materials.size());
        json unlit = {{"pbrMetallicRoughness",
                       {{"baseColorFactor", {1.0, 1.0, 1.0, 1.0}},
                        {"baseColorTexture", {{"index", images.size() - 1}, {"texCoord", 1}}}}},
                      {"extensions", {{"KHR_materials_unlit", json::object()}}}};
        const std::string& name = d.meshNames[i].empty() ? d.nodeNames[i] : d.meshNames[i];
        unlit["name"] =
            (name.empty() ? "object" + std::to_string(i) : name) + (back ? " (back)" : "") + " light map";
        materials.push_back(std::move(unlit));
      }
    }
    json primitives = json::array();
    for (size_t g = 0; next < sides.size() && sides[next].mesh == i; ++next) {
      const Side& s = sides[next];
      std::vector<uint32_t> indices = sp ? splitGroups[g].indices : s.group->indices;
      g += s.back || !m.twoSided ? 1 : 0;  // sides come front, back per group
      if (s.back) {
        for (size_t t = 0; t < indices.size(); t += 3) std::swap(indices[t + 1], indices[t + 2]);
      }
      // A light-textured mesh's triangles outside its atlas (rdb::inLightTexture) keep vertex colours.
      std::vector<uint32_t> textured, vertexLit;
      for (size_t t = 0; t < indices.size(); t += 3) {
        const bool inAtlas = sp && rdb::inLightTexture(sp->uv1[indices[t]]);
        (inAtlas ? textured : vertexLit).insert((inAtlas ? textured : vertexLit).end(), indices.begin() + std::ptrdiff_t(t),
                                               indices.begin() + std::ptrdiff_t(t + 3));
      }
      if (!textured.empty()) {
        primitives.push_back({{"attributes", {{"POSITION", position}, {"NORMAL", s.back ? backNormal : normal},
                                              {"TEXCOORD_1", texcoord}}},
                              {"indices", b.indices(textured)},
                              {"material", textureMaterial[s.back]}});
      }
      if (!vertexLit.empty()) {
        std::vector<vec3> colours;
        for (const Rgb& l : s.luminanceCdM2) colours.push_back(toneMap(l, ev100, ToneOperator::kReinhard));
        if (sp) colours = gather(colours, sp);
        primitives.push_back({{"attributes", {{"POSITION", position}, {"NORMAL", s.back ? backNormal : normal},
                                              {"COLOR_0", b.vec3s(colours)}}},
                              {"indices", b.indices(vertexLit)},
                              {"material", int(s.group->material)}});
      }
    }
    meshes.push_back(meshJson(d, i, std::move(primitives)));
    nodes.push_back(node(d, i, meshes.size() - 1));
  }
  doc["meshes"] = std::move(meshes);
  doc["materials"] = std::move(materials);
  if (!images.empty()) {
    // Linear filtering, clamped at the border (the atlas's padding holds dilated values).
    doc["samplers"] =
        json::array({{{"magFilter", 9729}, {"minFilter", 9729}, {"wrapS", 33071}, {"wrapT", 33071}}});
    json textures = json::array();
    for (size_t k = 0; k < images.size(); ++k) textures.push_back({{"source", k}, {"sampler", 0}});
    doc["images"] = std::move(images);
    doc["textures"] = std::move(textures);
  }
  doc["extensionsUsed"] = {"KHR_materials_unlit"};
  doc["extras"] = {{"fly", {{"toneMapping", "Reinhard"}, {"ev100", ev100}}}};
  nodesAndScene(doc, nodes);
  doc = b.finish(std::move(doc), "scene.bin");
  writeFileAtomic(dir / "scene.bin", b.bin());
  writeFileAtomic(dir / "scene.gltf", doc.dump(1) + "\n");
  return pngs;
}

// Mean over a mesh's vertices of the luminance of the irradiance, and of the relative standard error of the
// vertices that received light.
json sideSummary(std::span<const vec3> lux, std::span<const vec3> stdErrorLux) {
  double sum = 0.0, relSum = 0.0;
  size_t lit = 0;
  for (size_t v = 0; v < lux.size(); ++v) {
    const double e = luminance(lux[v]);
    sum += e;
    if (e > 0.0) {
      relSum += luminance(stdErrorLux[v]) / e;
      ++lit;
    }
  }
  return {{"mean_irradiance_lux", lux.empty() ? 0.0 : sum / double(lux.size())},
          {"mean_relative_error", lit == 0 ? 0.0 : relSum / double(lit)}};
}

// The same over a light texture's baked texels.
json textureSummary(const std::vector<Rgb>& lux, const std::vector<Rgb>& stdErrorLux,
                    const std::vector<uint8_t>& baked) {
  std::vector<vec3> l, e;
  for (size_t t = 0; t < baked.size(); ++t) {
    if (!baked[t]) continue;
    l.push_back(lux[t]);
    e.push_back(stdErrorLux[t]);
  }
  return sideSummary(l, e);
}

std::string shortest(double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

std::string shortest(float v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

}  // namespace

std::string convergenceCsv(const std::vector<raytracer::ConvergencePoint>& history, bool sunDirect) {
  std::string csv = std::string("seconds,samples,estimated_error,rays_per_second") +
                    (sunDirect ? ",sun_direct_estimated_error" : "") + "\n";
  for (const raytracer::ConvergencePoint& p : history) {
    csv += shortest(p.seconds) + "," + std::to_string(p.samples) + "," + shortest(p.relativeErrorP95) + "," +
           shortest(p.raysPerSecond) + (sunDirect ? "," + shortest(p.sunDirectRelativeErrorP95) : "") + "\n";
  }
  return csv;
}

void writeBakedScene(const fs::path& dir, const rdb::TraceRdb& rdb, const raytracer::VertexLightMaps& bakedMaps,
                     const BakeDescription& d) {
  const raytracer::VertexLightMaps maps = withPointReadErrors(bakedMaps);
  const size_t n = rdb.positionsM.size();
  if (maps.frontLux.size() != n || maps.frontStdErrorLux.size() != n || maps.backLux.size() != n ||
      maps.backStdErrorLux.size() != n || rdb.normals.size() != n) {
    throw std::invalid_argument("writeBakedScene: the light maps do not have one value per vertex");
  }
  if (d.meshNames.size() != rdb.meshes.size() || d.nodeNames.size() != rdb.meshes.size() ||
      d.materialNames.size() != rdb.materials.size()) {
    throw std::invalid_argument("writeBakedScene: the names do not match the meshes and materials");
  }
  if (!fs::create_directory(dir)) throw std::runtime_error("writeBakedScene: " + dir.string() + " exists");

  writeBakedGltf(dir, rdb, maps, d);
  writeFileAtomic(dir / "convergence.csv", convergenceCsv(maps.history, maps.hasSunDirect()));
  ImageSettings plotSettings = d.imageSettings;
  plotSettings.emplace_back("fly:scene", d.scenePath);
  plotSettings.emplace_back("fly:quantity",
                            "95th percentile of the relative standard error against run time");
  drawConvergencePlot(maps.history, dir / "convergence.png",
                      {.targetRelativeError = d.targetRelativeError,
                       .metadata = imageMetadata("Bake convergence", plotSettings, d.dotsPerInch)});
  std::vector<std::string> files = {"scene.gltf", "scene.bin", "convergence.csv", "convergence.png"};
  if (maps.lightTextures.size() != rdb.lightTextures.size()) {
    throw std::invalid_argument("writeBakedScene: the light textures do not match the TraceRdb's");
  }
  for (size_t k = 0; k < maps.lightTextures.size(); ++k) {
    const raytracer::LightTexture& tex = maps.lightTextures[k];
    const rdb::TraceLightTexture& lt = rdb.lightTextures[k];
    fs::create_directories(dir / "lightmaps");
    for (const bool sun : {false, true}) {
      if (sun && tex.frontSunDirectLux.empty()) continue;
      for (const bool back : {false, true}) {
        if (back && tex.backLux.empty()) continue;
        for (const bool stdError : {false, true}) {
          const std::vector<Rgb>& values =
              sun ? (back ? (stdError ? tex.backSunDirectStdErrorLux : tex.backSunDirectLux)
                          : (stdError ? tex.frontSunDirectStdErrorLux : tex.frontSunDirectLux))
                  : (back ? (stdError ? tex.backStdErrorLux : tex.backLux)
                          : (stdError ? tex.frontStdErrorLux : tex.frontLux));
          ImageRgbF image{int(tex.width), int(tex.height), {}};
          for (const Rgb& v : values) image.rgb.insert(image.rgb.end(), {v.r, v.g, v.b});
          const std::string file = lightTextureFile(lt.mesh, back, stdError, ".exr", sun);
          const std::string quantity = std::string(stdError ? "standard error of " : "") +
                                       (sun ? "irradiance straight from the sun's disc" : "irradiance");
          // Data, not a picture: the daylight it was baked under, no print resolution.
          ExrAttributes attributes =
              exrAttributes(imageMetadata("Light texture: " + quantity, d.imageSettings));
          attributes.insert(
              attributes.end(),
              {{"units", "lux"},
               {"fly:quantity", quantity},
               {"fly:side", back ? "back" : "front"},
               {"fly:object", std::to_string(lt.mesh)},
               {"fly:texelsPerMetre", shortest(lt.texelsPerMetre)},
               {"fly:uv", "TEXCOORD_1 of the object's mesh in scene.gltf; v = 0 is the top row"}});
          writeExr(dir / file, image, attributes);
          files.push_back(file);
        }
      }
    }
  }
  if (d.exportGltf) {
    const std::vector<std::string> pngs = writeExportGltf(dir / "export", rdb, maps, d);
    files.insert(files.end(), {"export/scene.gltf", "export/scene.bin"});
    for (const std::string& png : pngs) files.push_back("export/" + png);
  }

  json objects = json::array();
  size_t gltfMesh = 0;  // meshes without triangles have none (writeBakedGltf)
  for (size_t i = 0; i < rdb.meshes.size(); ++i) {
    const rdb::TraceMesh& m = rdb.meshes[i];
    json o = {{"sdb_mesh_id", m.sdbMeshId},
              {"sdb_node_id", m.sdbNodeId},
              {"gltf_mesh", m.triangleCount > 0 ? json(gltfMesh++) : json()},
              {"mesh_name", d.meshNames[i]},
              {"node_name", d.nodeNames[i]},
              {"vertices", m.vertexCount},
              {"triangles", m.triangleCount},
              {"two_sided", m.twoSided},
              {"samples", objectSamples(maps, m)},
              {"front", sideSummary(range(maps.frontLux, m), range(maps.frontStdErrorLux, m))}};
    if (m.twoSided) o["back"] = sideSummary(range(maps.backLux, m), range(maps.backStdErrorLux, m));
    if (i < maps.hiddenVertexSides.size() && maps.hiddenVertexSides[i] > 0)
      o["hidden_vertex_sides"] = maps.hiddenVertexSides[i];
    if (maps.hasSunDirect()) {
      o["front_sun_direct"] =
          sideSummary(range(maps.frontSunDirectLux, m), range(maps.frontSunDirectStdErrorLux, m));
      if (m.twoSided) {
        o["back_sun_direct"] =
            sideSummary(range(maps.backSunDirectLux, m), range(maps.backSunDirectStdErrorLux, m));
      }
    }
    if (m.lightTexture != rdb::TraceMesh::kNoLightTexture) {
      const rdb::TraceLightTexture& lt = rdb.lightTextures[m.lightTexture];
      const raytracer::LightTexture& tex = maps.lightTextures[m.lightTexture];
      json t = lightTextureFilesJson(i, m.twoSided, maps.hasSunDirect());
      t["width"] = lt.width;
      t["height"] = lt.height;
      t["texels_per_metre"] = lt.texelsPerMetre;
      t["automatic"] = lt.automatic;
      if (lt.automatic) t["automatic_reason"] = lt.automaticReason;
      t["uv"] = lt.fromTexcoord1 ? "TEXCOORD_1" : "generated";
      t["baked_texels"] = tex.bakedTexels;
      t["empty_texels"] = tex.emptyTexels;
      t["seam_edges"] = tex.seamEdges;
      t["samples"] = tex.samples;
      if (tex.hiddenTexelSides > 0) t["hidden_texel_sides"] = tex.hiddenTexelSides;
      t["front_summary"] = textureSummary(tex.frontLux, tex.frontStdErrorLux, tex.baked);
      if (m.twoSided) t["back_summary"] = textureSummary(tex.backLux, tex.backStdErrorLux, tex.baked);
      if (maps.hasSunDirect()) {
        t["front_sun_direct_summary"] =
            textureSummary(tex.frontSunDirectLux, tex.frontSunDirectStdErrorLux, tex.baked);
        if (m.twoSided) {
          t["back_sun_direct_summary"] =
              textureSummary(tex.backSunDirectLux, tex.backSunDirectStdErrorLux, tex.baked);
        }
      }
      o["light_texture"] = std::move(t);
    }
    objects.push_back(std::move(o));
  }
  const float finalError = maps.history.empty() ? 0.0f : maps.history.back().relativeErrorP95;
  // The sun whose direct light the bake kept apart (sunlight mode draws it in real time at any other time).
  json sunDirect = nullptr;
  if (maps.hasSunDirect()) {
    const vec3& towardsSun = rdb.sun.directionWorld;
    const Rgb& en = rdb.sun.normalIlluminanceLux;
    const double elevationDeg = radToDeg(std::asin(std::clamp(double(towardsSun.y), -1.0, 1.0)));
    const json& site = d.daylight.is_object() ? d.daylight.value("site", json()) : json();
    sunDirect = {
        {"direction_world", {towardsSun.x, towardsSun.y, towardsSun.z}},
        {"elevation_deg", elevationDeg},
        {"normal_illuminance_lux", {en.r, en.g, en.b}},
        {"normal_illuminance_luminance_lux", luminance(en)},
        {"time", d.daylight.is_object() ? d.daylight.value("time", json()) : json()},
        {"time_zone", site.is_object() ? site.value("time_zone", json()) : json()},
        {"sun_direction", d.daylight.is_object() ? d.daylight.value("sun_direction", json()) : json()},
        {"relative_error_p95", maps.history.empty() ? 0.0f : maps.history.back().sunDirectRelativeErrorP95}};
  }
  const json manifest = {
      {"format", kBakedSceneFormat},
      {"format_version", kBakedSceneFormatVersion},
      {"fly_version", kFlyVersion},
      {"scene", d.scenePath},
      {"scene_absolute", fs::absolute(d.scenePath).lexically_normal().string()},
      // From the baked directory (its temporary is a sibling of it, so the path is the same): a project
      // folder copied or moved whole keeps finding its scene.
      {"scene_from_bake", fs::absolute(d.scenePath)
                              .lexically_normal()
                              .lexically_relative(fs::absolute(dir).lexically_normal())
                              .generic_string()},
      {"settings", d.settings},
      {"bounce_cap_bias", d.bounceCapBias},
      {"daylight", d.daylight},
      {"samples_per_vertex", maps.samplesPerVertex},
      {"rays", maps.rays},
      {"bake_seconds", maps.seconds},
      {"relative_error_p95", finalError},
      {"unfilled_vertices", maps.unfilledVertices},
      {"sun_direct", sunDirect},
      {"timings_s", d.timingsS},
      {"units", {{"irradiance", "lux"}, {"length", "m"}, {"frame", "glTF world: +Y up, right-handed"}}},
      {"objects", std::move(objects)},
      {"files", files},
  };
  writeFileAtomic(dir / "manifest.json", manifest.dump(2) + "\n");
}

void checkBakeOutput(const fs::path& dir) {
  std::error_code ec;
  if (fs::exists(fs::symlink_status(dir, ec)) && !isBakedScene(dir)) {
    throw UsageError("--out " + dir.string() +
                     ": exists and is not a baked scene (no manifest.json); a bake replaces only an earlier "
                     "bake — give a new directory or remove this one");
  }
}

void writeDirectoryAtomic(const fs::path& dir, const std::function<void(const fs::path& tmp)>& fill) {
  checkBakeOutput(dir);
  const fs::path parent = dir.has_parent_path() ? dir.parent_path() : fs::path(".");
  const std::string base = dir.filename().string();
  std::random_device rd;
  const std::string suffix = std::to_string(rd());
  const fs::path tmp = parent / (base + ".tmp-" + suffix);
  const fs::path old = parent / (base + ".old-" + suffix);
  try {
    fs::create_directories(parent);
    fill(tmp);
    if (fs::exists(dir)) {
      fs::rename(dir, old);
      try {
        fs::rename(tmp, dir);
      } catch (...) {
        fs::rename(old, dir);  // put the earlier bake back
        throw;
      }
      // The new bake is in place: failing to delete the old one leaves clutter, not a wrong result.
      std::error_code ec;
      fs::remove_all(old, ec);
    } else {
      fs::rename(tmp, dir);
    }
  } catch (...) {
    std::error_code ec;
    fs::remove_all(tmp, ec);
    throw;
  }
}

uint32_t objectSamples(const raytracer::VertexLightMaps& maps, const rdb::TraceMesh& m) {
  uint32_t samples = 0;
  for (size_t v = m.firstVertex; v < m.firstVertex + m.vertexCount && v < maps.frontSamples.size(); ++v)
    samples = std::max(samples, maps.frontSamples[v]);
  return samples;
}

}  // namespace fly::cli
