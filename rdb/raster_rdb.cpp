#include "rdb/raster_rdb.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <optional>
#include <string>
#include <unordered_map>

#include "base/error.h"
#include "base/spot_cone.h"
#include "rdb/placed_mesh.h"
#include "rdb/trace_rdb_build.h"
#include "sdb/features.h"
#include "sdb/scene.h"

namespace fly::rdb {

bool RasterRdb::operator==(const RasterRdb& o) const {
  auto sameSky = [](const std::optional<RasterSky>& a, const std::optional<RasterSky>& b) {
    if (a.has_value() != b.has_value()) return false;
    if (!a) return true;
    return a->width == b->width && a->height == b->height && a->radianceCdM2 == b->radianceCdM2 &&
           a->hasSun == b->hasSun && a->sunDirWorld == b->sunDirWorld &&
           a->sunRadianceCdM2 == b->sunRadianceCdM2 && a->sunHalfAngleRad == b->sunHalfAngleRad;
  };
  return positionsM == o.positionsM && normals == o.normals && cornerFactor == o.cornerFactor &&
         indices == o.indices && meshes == o.meshes && materials == o.materials &&
         boundsM.min == o.boundsM.min && boundsM.max == o.boundsM.max && frontLux == o.frontLux &&
         backLux == o.backLux && frontSunDirectLux == o.frontSunDirectLux &&
         backSunDirectLux == o.backSunDirectLux && lightMapUv == o.lightMapUv &&
         lightTextures == o.lightTextures && uv0 == o.uv0 && uv1 == o.uv1 && colors == o.colors &&
         tangents == o.tangents && textures == o.textures && measuredBrdfs == o.measuredBrdfs && lights == o.lights &&
         goniometricCd == o.goniometricCd && ambient == o.ambient && daylightAmbient == o.daylightAmbient &&
         ambientClosure == o.ambientClosure && cameras == o.cameras && sameSky(sky, o.sky) && variants == o.variants &&
         planarReflectors == o.planarReflectors && cubeReflectors == o.cubeReflectors;
}

bool RasterRdb::shadedPerFragment(const RasterMesh& mesh) const {
  const RasterMaterial& m = materials[mesh.material];
  return m.hasTexture() || m.alphaMode != RasterAlphaMode::kOpaque || m.measured != RasterTextureRef::kNone ||
         m.anisotropic || mesh.hasColors || mesh.planarReflector != RasterTextureRef::kNone ||
         mesh.cubeReflector != RasterTextureRef::kNone || m.hasReflectionFog();
}

namespace {

// An entry of the texture table: an SDB texture and whether it is sampled as sRGB.
struct TextureKey {
  uint32_t sdbTextureId = 0;
  bool srgb = false;
  bool operator==(const TextureKey&) const = default;
};

// Where lowerRasterMaterial finds (or puts) a texture's index in RasterRdb::textures: `keys` is the table in
// order; with `append`, a texture not yet in it is added, else it gets kNone and `missing` is set.
struct TextureTable {
  std::vector<TextureKey> keys;
  bool append = true;
  bool missing = false;

  uint32_t indexOf(TextureKey k) {
    const auto it = std::find(keys.begin(), keys.end(), k);
    if (it != keys.end()) return uint32_t(it - keys.begin());
    if (!append) {
      missing = true;
      return RasterTextureRef::kNone;
    }
    keys.push_back(k);
    return uint32_t(keys.size() - 1);
  }
};

// Glass to the engine: a material that transmits (the energy rule's transmission at normal incidence), clear
// or frosted, drawn as a thin pane in its own pass (RasterMaterial::transmission).
bool engineGlass(const sdb::Material& m) { return maxComponent(m.effective().transmission) > 0.0f; }

// Anisotropic to the engine: an anisotropic material (sdb::Material::isAnisotropic) that is not glass, has
// an analytic lobe (not measured) and reflects something.
bool engineAnisotropic(const sdb::Material& m) {
  return m.isAnisotropic() && !engineGlass(m) && !m.isMeasured() &&
         maxComponent(glm::clamp(m.reflectionAt(1.0f), Rgb(0.0f), Rgb(1.0f))) > 0.0f;
}

// Whether the engine reads m's glossiness texture: a material that is not glass, with an analytic lobe (not
// measured) that reflects something (otherwise the width it sets shows nowhere).
bool engineGlossinessTextured(const sdb::Material& m) {
  return m.reflectionGlossinessTexture && !engineGlass(m) && !m.isMeasured() &&
         maxComponent(glm::clamp(m.reflectionAt(1.0f), Rgb(0.0f), Rgb(1.0f))) > 0.0f;
}

RasterTextureRef lowerTextureRef(const sdb::TextureRef& ref, bool srgb, TextureTable& table) {
  RasterTextureRef r;
  if (!ref) return r;
  r.texture = table.indexOf({ref.texture.value, srgb});
  r.texCoord = uint32_t(std::clamp(ref.texCoord, 0, 1));
  // KHR_texture_transform: uv' = offset + R · (scale ⊙ uv), R = [cos, sin; −sin, cos] (row-major).
  const sdb::UvTransform& t = ref.transform;
  const float c = std::cos(t.rotationRad), s = std::sin(t.rotationRad);
  r.uvRow0 = vec3(c * t.scale.x, s * t.scale.y, t.offset.x);
  r.uvRow1 = vec3(-s * t.scale.x, c * t.scale.y, t.offset.y);
  auto wrap = [](sdb::WrapMode w) {
    switch (w) {
      case sdb::WrapMode::kClampToEdge:
        return RasterWrap::kClampToEdge;
      case sdb::WrapMode::kMirroredRepeat:
        return RasterWrap::kMirroredRepeat;
      case sdb::WrapMode::kRepeat:
        break;
    }
    return RasterWrap::kRepeat;
  };
  r.wrapS = wrap(ref.wrapS);
  r.wrapT = wrap(ref.wrapT);
  r.magFilter = ref.magFilter == sdb::MagFilter::kNearest ? RasterMagFilter::kNearest : RasterMagFilter::kLinear;
  switch (ref.minFilter) {
    case sdb::MinFilter::kNearest:
      r.minFilter = RasterMinFilter::kNearest;
      break;
    case sdb::MinFilter::kLinear:
      r.minFilter = RasterMinFilter::kLinear;
      break;
    case sdb::MinFilter::kNearestMipmapNearest:
      r.minFilter = RasterMinFilter::kNearestMipmapNearest;
      break;
    case sdb::MinFilter::kLinearMipmapNearest:
      r.minFilter = RasterMinFilter::kLinearMipmapNearest;
      break;
    case sdb::MinFilter::kNearestMipmapLinear:
      r.minFilter = RasterMinFilter::kNearestMipmapLinear;
      break;
    case sdb::MinFilter::kLinearMipmapLinear:
      r.minFilter = RasterMinFilter::kLinearMipmapLinear;
      break;
  }
  return r;
}

RasterMaterial lowerRasterMaterial(const sdb::Material& m, uint32_t sdbMaterialId, TextureTable& table) {
  RasterMaterial r;
  r.diffuse = m.effective().diffuse;
  r.specular = glm::clamp(m.reflectionAt(1.0f), Rgb(0.0f), Rgb(1.0f));
  r.ggxAlpha = m.reflectionGlossiness * m.reflectionGlossiness;
  if (std::max({r.specular.r, r.specular.g, r.specular.b}) > 0.0f) {
    r.environmentF90 = m.reflectionModel == sdb::ReflectionModel::kUniform
                           ? r.specular
                           : glm::clamp(m.reflectionColor, Rgb(0.0f), Rgb(1.0f));
  }
  r.emissionCdM2 = m.emissionLuminance;
  r.emissionDisplay = m.emissionDisplay;
  if (engineGlass(m)) {
    r.transmission = glm::clamp(m.transmissionColor, Rgb(0.0f), Rgb(1.0f));
    if (m.transmissionTexture) {
      // The diffuse input after the reflection's share only, (1 − r′) d: the texel's (1 − t) is the
      // transmission's share (sdb::applyEnergyRule per texel).
      r.transmissionTexture = lowerTextureRef(m.transmissionTexture, false, table);
      r.diffuse = sdb::applyEnergyRule(m.diffuseColor, m.reflectionAt(1.0f), Rgb(0.0f)).diffuse;
    }
    const float alphaT = m.transmissionGlossiness * m.transmissionGlossiness;
    r.transmissionAlpha = alphaT < sdb::kSmoothAlpha ? 0.0f : alphaT;
    r.reflection = glm::clamp(m.reflectionColor, Rgb(0.0f), Rgb(1.0f));
    r.fresnelF0 = m.reflectionModel == sdb::ReflectionModel::kFresnel ? sdb::fresnelF0(m.ior) : -1.0f;
  } else if (m.reflectionModel == sdb::ReflectionModel::kUniform) {
    r.reflection = glm::clamp(m.reflectionColor, Rgb(0.0f), Rgb(1.0f));
  }
  {
    r.baseColorTexture = lowerTextureRef(m.diffuseTexture, true, table);
    r.reflectionTinted = m.reflectionTextureSrgb && m.reflectionTexture && m.diffuseTexture &&
                         m.reflectionTexture.texture == m.diffuseTexture.texture &&
                         m.reflectionTexture.texCoord == m.diffuseTexture.texCoord &&
                         m.reflectionTexture.transform.offset == m.diffuseTexture.transform.offset &&
                         m.reflectionTexture.transform.rotationRad == m.diffuseTexture.transform.rotationRad &&
                         m.reflectionTexture.transform.scale == m.diffuseTexture.transform.scale;
    r.emissionTexture = lowerTextureRef(m.emissionTexture, true, table);
    r.normalTexture = lowerTextureRef(m.bumpTexture, false, table);
    r.normalScale = std::max(0.0f, m.bumpScale);
    if (engineAnisotropic(m)) {
      r.anisotropic = true;
      r.anisotropyU = std::clamp(m.anisotropyU, 0.0f, 1.0f);
      r.anisotropyV = std::clamp(m.anisotropyV, 0.0f, 1.0f);
      r.anisotropyRotationRad = m.anisotropyRotationRad;
      r.anisotropyTexture = lowerTextureRef(m.anisotropyTexture, false, table);
      r.anisotropyRotationTexture = lowerTextureRef(m.anisotropyRotationTexture, false, table);
    }
    if (engineGlossinessTextured(m)) {
      r.glossinessTexture = lowerTextureRef(m.reflectionGlossinessTexture, false, table);
    }
    if (m.metalnessTexture && !m.isMeasured()) {
      r.metalnessTexture = lowerTextureRef(m.metalnessTexture, false, table);
      r.metalness = std::clamp(m.metalnessFactor, 0.0f, 1.0f);
      r.diffuse = glm::clamp(m.diffuseColor, Rgb(0.0f), Rgb(1.0f));
    }
    switch (m.alphaMode) {
      case sdb::AlphaMode::kOpaque:
        r.alphaMode = RasterAlphaMode::kOpaque;
        break;
      case sdb::AlphaMode::kMask:
        r.alphaMode = RasterAlphaMode::kMask;
        break;
      case sdb::AlphaMode::kBlend:
        // Glass lets light through by its transmittance alone: a pane's coverage is whole.
        r.alphaMode = engineGlass(m) ? RasterAlphaMode::kOpaque : RasterAlphaMode::kBlend;
        break;
    }
    r.alphaCutoff = std::clamp(m.alphaCutoff, 0.0f, 1.0f);
    r.opacity = std::clamp(m.opacity, 0.0f, 1.0f);
  }
  if (m.showsPlanarReflection() && !engineGlass(m) && !m.isMeasured()) {
    r.mirrorLike = true;
    r.mirrorReflection = glm::clamp(m.reflectionColor, Rgb(0.0f), Rgb(1.0f));
    r.mirrorF0 = m.reflectionModel == sdb::ReflectionModel::kFresnel ? sdb::fresnelF0(m.ior) : -1.0f;
  }
  if (!engineGlass(m) && !m.isMeasured()) {
    r.cubeMapAlways = m.showsCubeMapReflection(true);
    r.cubeMapOnCurved = m.showsCubeMapReflection(false);
    if (std::isfinite(m.reflectionFogDistanceM) && maxComponent(r.specular) > 0.0f) {
      r.reflectionFogDistanceM = m.reflectionFogDistanceM;
      r.reflectionFogColor = glm::clamp(m.reflectionFogColor, Rgb(0.0f), Rgb(1.0f));
    }
  }
  r.sdbMaterialId = sdbMaterialId;
  return r;
}

// Whether two blocks of one material read the same textures with the same UV sets and use coverage the same
// way: then an edit between them changes only the block (factors, transforms, cut-off, opacity).
bool sameTextureLayout(const RasterMaterial& a, const RasterMaterial& b) {
  auto same = [](const RasterTextureRef& x, const RasterTextureRef& y) {
    return x.texture == y.texture && x.texCoord == y.texCoord;
  };
  return same(a.baseColorTexture, b.baseColorTexture) && same(a.emissionTexture, b.emissionTexture) &&
         same(a.normalTexture, b.normalTexture) && same(a.anisotropyTexture, b.anisotropyTexture) &&
         same(a.anisotropyRotationTexture, b.anisotropyRotationTexture) &&
         same(a.glossinessTexture, b.glossinessTexture) &&
         same(a.transmissionTexture, b.transmissionTexture) && same(a.metalnessTexture, b.metalnessTexture) &&
         a.anisotropic == b.anisotropic &&
         a.alphaMode == b.alphaMode && a.mirrorLike == b.mirrorLike &&
         a.cubeMapOnCurved == b.cubeMapOnCurved && a.cubeMapAlways == b.cubeMapAlways;
}

// An SDB texture as RGBA8 (RasterTexture). InputError when its pixels do not match its size.
RasterTexture lowerTexture(const sdb::Scene& scene, const TextureKey& key) {
  const sdb::Texture& t = scene.texture(sdb::TextureId{key.sdbTextureId});
  const int bytes = t.bitsPerChannel == 16 ? 2 : 1;
  if (t.width < 1 || t.height < 1 || t.channels < 1 || t.channels > 4 ||
      (t.bitsPerChannel != 8 && t.bitsPerChannel != 16) ||
      t.pixels.size() != size_t(t.width) * size_t(t.height) * size_t(t.channels) * size_t(bytes)) {
    throw InputError({t.sourcePath}, "texture \"" + t.name + "\" has " + std::to_string(t.pixels.size()) +
                                         " bytes, which do not match its " + std::to_string(t.width) + "×" +
                                         std::to_string(t.height) + " pixels of " + std::to_string(t.channels) +
                                         " " + std::to_string(t.bitsPerChannel) + "-bit channels",
                     "re-export the image");
  }
  RasterTexture r;
  r.sdbTextureId = key.sdbTextureId;
  r.srgb = key.srgb;
  r.width = uint32_t(t.width);
  r.height = uint32_t(t.height);
  const size_t texels = size_t(t.width) * size_t(t.height);
  r.rgba8.resize(texels * 4);
  const int ch = t.channels;
  for (size_t i = 0; i < texels; ++i) {
    uint8_t v[4] = {0, 0, 0, 255};
    for (int c = 0; c < ch; ++c) {
      const size_t at = (i * size_t(ch) + size_t(c)) * size_t(bytes);
      if (bytes == 2) {
        uint16_t x;
        std::memcpy(&x, &t.pixels[at], 2);
        v[c] = uint8_t((uint32_t(x) * 255u + 32767u) / 65535u);
      } else {
        v[c] = t.pixels[at];
      }
    }
    uint8_t* out = &r.rgba8[4 * i];
    if (ch <= 2) {  // grey, grey + alpha
      out[0] = out[1] = out[2] = v[0];
      out[3] = ch == 2 ? v[1] : 255;
    } else {
      out[0] = v[0];
      out[1] = v[1];
      out[2] = v[2];
      out[3] = ch == 4 ? v[3] : 255;
    }
  }
  return r;
}

// Which per-vertex attributes a mesh with material `m` needs (RasterRdb::uv0 … tangents).
struct AttributeNeeds {
  bool uv[2] = {false, false};
  bool tangents = false;
  int tangentSet = 0;  // the UV set of the normal map, else of the anisotropy's textures (RasterRdb::tangents)
  bool colors = false;
};

AttributeNeeds attributeNeeds(const sdb::Material& m, const sdb::Mesh& mesh) {
  AttributeNeeds n;
  const bool anisotropic = engineAnisotropic(m);
  for (const sdb::TextureRef* ref :
       {&m.diffuseTexture, &m.emissionTexture, &m.bumpTexture, &m.transmissionTexture, &m.metalnessTexture}) {
    if (*ref) n.uv[std::clamp(ref->texCoord, 0, 1)] = true;
  }
  if (anisotropic) {
    for (const sdb::TextureRef* ref : {&m.anisotropyTexture, &m.anisotropyRotationTexture}) {
      if (*ref) n.uv[std::clamp(ref->texCoord, 0, 1)] = true;
    }
  }
  if (engineGlossinessTextured(m)) n.uv[std::clamp(m.reflectionGlossinessTexture.texCoord, 0, 1)] = true;
  if (m.bumpTexture) {
    n.tangents = true;
    n.tangentSet = std::clamp(m.bumpTexture.texCoord, 0, 1);
  }
  if (anisotropic) {
    n.tangents = true;
    // The normal map's UV set where there is one (glTF defines both in its tangent space; the baker's rule,
    // rdb/trace_rdb_build.cpp), else the anisotropy textures'.
    if (!m.bumpTexture && (m.anisotropyTexture || m.anisotropyRotationTexture)) {
      const sdb::TextureRef& first = m.anisotropyTexture ? m.anisotropyTexture : m.anisotropyRotationTexture;
      n.tangentSet = std::clamp(first.texCoord, 0, 1);
    }
  }
  n.colors = !mesh.colors.empty();
  return n;
}

// Any unit vector perpendicular to unit `n`.
vec3 perpendicular(const vec3& n) {
  const vec3 a = std::abs(n.x) < 0.9f ? vec3(1, 0, 0) : vec3(0, 1, 0);
  return glm::normalize(glm::cross(n, a));
}

// The world tangent frame of a normal-mapped mesh's vertices (RasterRdb::tangents): the file's, placed, or
// generated from UV set `uv` (Lengyel's method, see raster_rdb.h).
std::vector<vec4> placedTangents(const sdb::Mesh& mesh, const PlacedMesh& placed, const mat4& worldFromLocal,
                                 const std::vector<vec2>& uv) {
  const size_t n = mesh.vertexCount();
  std::vector<vec4> out(n);
  if (!mesh.tangents.empty()) {
    const glm::dmat3 linear(worldFromLocal);
    const float handedness = glm::determinant(linear) < 0.0 ? -1.0f : 1.0f;
    for (size_t i = 0; i < n; ++i) {
      const vec3 normal = placed.normals[i];
      const dvec3 t = linear * dvec3(vec3(mesh.tangents[i]));
      const std::optional<vec3> u = unitOrNone(t - glm::dot(t, dvec3(normal)) * dvec3(normal));
      out[i] = vec4(u.value_or(perpendicular(normal)), (mesh.tangents[i].w < 0.0f ? -1.0f : 1.0f) * handedness);
    }
    return out;
  }
  std::vector<dvec3> dpdu(n, dvec3(0.0)), dpdup(n, dvec3(0.0));  // ∂p/∂u and ∂p/∂(−v) sums
  if (uv.size() == n) {
    for (size_t t = 0; t + 2 < placed.indices.size(); t += 3) {
      const uint32_t* v = &placed.indices[t];
      const dvec3 p0(placed.positionsM[v[0]]);
      const dvec3 e1 = dvec3(placed.positionsM[v[1]]) - p0, e2 = dvec3(placed.positionsM[v[2]]) - p0;
      // Texture-space edges with the image's up (−v) as the second axis.
      const double du1 = double(uv[v[1]].x) - uv[v[0]].x, dv1 = -(double(uv[v[1]].y) - uv[v[0]].y);
      const double du2 = double(uv[v[2]].x) - uv[v[0]].x, dv2 = -(double(uv[v[2]].y) - uv[v[0]].y);
      const double det = du1 * dv2 - du2 * dv1;
      if (!(std::abs(det) > 1e-20) || !std::isfinite(det)) continue;  // no UV area
      const dvec3 su = (e1 * dv2 - e2 * dv1) / det, sv = (e2 * du1 - e1 * du2) / det;
      for (int k = 0; k < 3; ++k) {
        dpdu[v[k]] += su;
        dpdup[v[k]] += sv;
      }
    }
  }
  for (size_t i = 0; i < n; ++i) {
    const dvec3 normal(placed.normals[i]);
    const std::optional<vec3> u = unitOrNone(dpdu[i] - glm::dot(dpdu[i], normal) * normal);
    const vec3 t = u.value_or(perpendicular(placed.normals[i]));
    const float w = glm::dot(glm::cross(normal, dvec3(t)), dpdup[i]) < 0.0 ? -1.0f : 1.0f;
    out[i] = vec4(t, w);
  }
  return out;
}

// Splits the vertices of light-textured mesh `rm` (its SDB vertices and kept triangles already in `rdb`)
// where the atlas's charts meet, as the baked scene.gltf does (cli/baked_scene.h): each SDB vertex keeps the
// UV of its first corner ((0, 0) for a vertex of no triangle), a copy is appended for every further UV, and
// the triangles' indices are redirected to the copies. Fills `copySource` (per copy: its SDB vertex) and `uv`
// (per vertex of the split mesh) and extends rm.vertexCount. InputError when the texture does not match the
// mesh (a bake of an edited scene).
void splitAtSeams(RasterRdb& rdb, RasterMesh& rm, const sdb::Mesh& mesh, const MeshLightTexture& texture,
                  const sdb::Scene& scene, std::vector<uint32_t>& copySource, std::vector<vec2>& uv) {
  const size_t texels = size_t(texture.width) * texture.height;
  const bool finite = std::all_of(texture.cornerUv.begin(), texture.cornerUv.end(),
                                  [](const vec2& c) { return std::isfinite(c.x) && std::isfinite(c.y); });
  if (texture.cornerUv.size() != rm.indexCount || texels == 0 || texture.frontLux.size() != texels ||
      (!texture.backLux.empty() && texture.backLux.size() != texels) ||
      (!texture.frontSunDirectLux.empty() && texture.frontSunDirectLux.size() != texels) ||
      (!texture.backSunDirectLux.empty() && texture.backSunDirectLux.size() != texels) || !finite) {
    throw InputError({scene.sourcePath.string()},
                     "the light texture of mesh \"" + mesh.name + "\" has " +
                         std::to_string(texture.cornerUv.size() / 3) + " triangles but the mesh has " +
                         std::to_string(rm.indexCount / 3) + " with area (or its texels do not match its " +
                         std::to_string(texture.width) + "×" + std::to_string(texture.height) + " size)",
                     "bake the scene again: it changed since the light maps were made");
  }
  uv.assign(rm.vertexCount, vec2(0.0f));
  std::vector<bool> assigned(rm.vertexCount, false);
  std::vector<std::vector<uint32_t>> copies(rm.vertexCount);  // local vertices holding each SDB vertex
  for (uint32_t c = 0; c < rm.indexCount; ++c) {
    uint32_t& index = rdb.indices[rm.firstIndex + c];
    const uint32_t v = index - rm.firstVertex;
    const vec2 cornerUv = texture.cornerUv[c];
    if (!assigned[v]) {
      assigned[v] = true;
      uv[v] = cornerUv;
      copies[v].push_back(v);
      continue;
    }
    auto same =
        std::find_if(copies[v].begin(), copies[v].end(), [&](uint32_t o) { return uv[o] == cornerUv; });
    if (same == copies[v].end()) {
      same = copies[v].insert(copies[v].end(), uint32_t(uv.size()));
      copySource.push_back(v);
      uv.push_back(cornerUv);
      rdb.positionsM.push_back(rdb.positionsM[rm.firstVertex + v]);
      rdb.normals.push_back(rdb.normals[rm.firstVertex + v]);
    }
    index = rm.firstVertex + *same;
  }
  rm.vertexCount = uint32_t(uv.size());
}

// Geometry and light maps: every placed (node, mesh) pair, vertices in SDB order (light-textured meshes:
// followed by their seam copies).
void buildGeometry(RasterRdb& rdb, const sdb::Scene& scene, const LightMapStore* lightMaps) {
  rdb.positionsM.clear();
  rdb.normals.clear();
  rdb.indices.clear();
  rdb.meshes.clear();
  rdb.frontLux.clear();
  rdb.backLux.clear();
  rdb.frontSunDirectLux.clear();
  rdb.backSunDirectLux.clear();
  rdb.lightMapUv.clear();
  rdb.lightTextures.clear();
  rdb.uv0.clear();
  rdb.uv1.clear();
  rdb.colors.clear();
  rdb.tangents.clear();
  rdb.boundsM = Bounds3{};
  std::vector<const MeshLightMap*> maps;
  std::vector<std::vector<uint32_t>> copySource;  // per mesh: the source (SDB) vertex of each seam copy
  std::vector<std::vector<vec2>> meshUv;          // per mesh: light-map UV per vertex, or empty
  // Per mesh: its SDB vertices' texture attributes where it needs them, else empty.
  struct MeshAttributes {
    std::vector<vec2> uv0, uv1;
    std::vector<vec4> colors, tangents;
  };
  std::vector<MeshAttributes> attributes;
  scene.forEachNode([&](sdb::NodeId nodeId, const mat4& worldFromLocal) {
    for (sdb::MeshId meshId : scene.node(nodeId).meshes) {
      const sdb::Mesh& mesh = scene.mesh(meshId);
      RasterMesh rm;
      rm.sdbNodeId = nodeId.value;
      rm.sdbMeshId = meshId.value;
      rm.firstVertex = uint32_t(rdb.positionsM.size());
      rm.vertexCount = uint32_t(mesh.vertexCount());
      rm.firstIndex = uint32_t(rdb.indices.size());
      rm.twoSided = mesh.twoSided;
      const PlacedMesh placed = placeMesh(mesh, worldFromLocal);
      for (const vec3& p : placed.positionsM) {
        rdb.positionsM.push_back(p);
        rdb.boundsM.extend(p);
      }
      for (uint32_t v : placed.indices) rdb.indices.push_back(rm.firstVertex + v);
      rm.indexCount = uint32_t(rdb.indices.size()) - rm.firstIndex;
      rdb.normals.insert(rdb.normals.end(), placed.normals.begin(), placed.normals.end());
      const MeshLightMap* map = lightMaps ? lightMaps->find(nodeId.value, meshId.value) : nullptr;
      if (map) {
        const bool sunDirect = lightMaps->sun.has_value();
        if (map->frontLux.size() != mesh.vertexCount() ||
            (!map->backLux.empty() && map->backLux.size() != mesh.vertexCount()) ||
            (sunDirect && map->frontSunDirectLux.size() != mesh.vertexCount()) ||
            (sunDirect && map->backSunDirectLux.size() != map->backLux.size())) {
          throw InputError({scene.sourcePath.string()},
                           "the light map of mesh \"" + mesh.name + "\" has " +
                               std::to_string(map->frontLux.size()) + " values but the mesh has " +
                               std::to_string(mesh.vertexCount()) + " vertices",
                           "bake the scene again: it changed since the light maps were made");
        }
        rm.hasLightMap = true;
      }
      std::vector<uint32_t> copies;
      std::vector<vec2> uv;
      if (map && map->lightTexture) {
        splitAtSeams(rdb, rm, mesh, *map->lightTexture, scene, copies, uv);
        rm.lightTexture = uint32_t(rdb.lightTextures.size());
        const MeshLightTexture& t = *map->lightTexture;
        RasterLightTexture r{t.width, t.height, t.frontLux, {}, {}, {}};
        if (mesh.twoSided) r.backLux = t.backLux;
        if (lightMaps->sun) {
          if (t.frontSunDirectLux.size() != t.frontLux.size() ||
              t.backSunDirectLux.size() != t.backLux.size()) {
            throw InputError({scene.sourcePath.string()},
                             "the light texture of mesh \"" + mesh.name +
                                 "\" has no sun-direct texels to match its irradiance",
                             "bake the scene again");
          }
          r.frontSunDirectLux = t.frontSunDirectLux;
          if (mesh.twoSided) r.backSunDirectLux = t.backSunDirectLux;
        }
        rdb.lightTextures.push_back(std::move(r));
      }
      const AttributeNeeds needs = attributeNeeds(scene.material(mesh.material), mesh);
      MeshAttributes a;
      const std::vector<vec2>* sourceUv[2] = {&mesh.uv0, &mesh.uv1};
      std::vector<vec2>* uvOut[2] = {&a.uv0, &a.uv1};
      for (int set = 0; set < 2; ++set) {
        if (!needs.uv[set]) continue;
        *uvOut[set] = sourceUv[set]->size() == mesh.vertexCount() ? *sourceUv[set]
                                                                 : std::vector<vec2>(mesh.vertexCount(), vec2(0.0f));
      }
      if (needs.colors) {
        a.colors = mesh.colors;
        rm.hasColors = true;
      }
      if (needs.tangents) a.tangents = placedTangents(mesh, placed, worldFromLocal, *sourceUv[needs.tangentSet]);
      attributes.push_back(std::move(a));
      maps.push_back(map);
      copySource.push_back(std::move(copies));
      meshUv.push_back(std::move(uv));
      rdb.meshes.push_back(rm);
    }
  });
  // The texture attributes in flat arrays, where some mesh has them; seam copies take their source's.
  const auto flatten = [&](auto& out, auto member, const auto& fill) {
    const bool any = std::any_of(attributes.begin(), attributes.end(),
                                 [&](const MeshAttributes& a) { return !(a.*member).empty(); });
    if (!any) return;
    out.assign(rdb.positionsM.size(), fill);
    for (size_t i = 0; i < attributes.size(); ++i) {
      const auto& values = attributes[i].*member;
      if (values.empty()) continue;
      const RasterMesh& rm = rdb.meshes[i];
      std::copy(values.begin(), values.end(), out.begin() + rm.firstVertex);
      for (size_t k = 0; k < copySource[i].size(); ++k)
        out[rm.firstVertex + values.size() + k] = values[copySource[i][k]];
    }
  };
  flatten(rdb.uv0, &MeshAttributes::uv0, vec2(0.0f));
  flatten(rdb.uv1, &MeshAttributes::uv1, vec2(0.0f));
  flatten(rdb.colors, &MeshAttributes::colors, vec4(1.0f));
  flatten(rdb.tangents, &MeshAttributes::tangents, vec4(1.0f, 0.0f, 0.0f, 1.0f));
  const bool anyMap =
      std::any_of(maps.begin(), maps.end(), [](const MeshLightMap* m) { return m != nullptr; });
  bool anyBack = false;
  for (size_t i = 0; i < maps.size(); ++i)
    anyBack |= maps[i] && rdb.meshes[i].twoSided && !maps[i]->backLux.empty();
  // The sun-direct parts come with every light map of a bake that kept them (LightMapStore::sun).
  const bool sunDirect = anyMap && lightMaps->sun.has_value();
  if (anyMap) rdb.frontLux.assign(rdb.positionsM.size(), Rgb(0.0f));
  if (anyBack) rdb.backLux.assign(rdb.positionsM.size(), Rgb(0.0f));
  if (sunDirect) rdb.frontSunDirectLux.assign(rdb.positionsM.size(), Rgb(0.0f));
  if (sunDirect && anyBack) rdb.backSunDirectLux.assign(rdb.positionsM.size(), Rgb(0.0f));
  // A mesh's seam copies (after its SDB vertices) carry their source vertex's values.
  const auto place = [&](std::vector<Rgb>& out, const std::vector<Rgb>& values, size_t i) {
    const RasterMesh& rm = rdb.meshes[i];
    std::copy(values.begin(), values.end(), out.begin() + rm.firstVertex);
    for (size_t k = 0; k < copySource[i].size(); ++k)
      out[rm.firstVertex + values.size() + k] = values[copySource[i][k]];
  };
  for (size_t i = 0; i < maps.size(); ++i) {
    if (!maps[i]) continue;
    place(rdb.frontLux, maps[i]->frontLux, i);
    if (sunDirect) place(rdb.frontSunDirectLux, maps[i]->frontSunDirectLux, i);
    if (anyBack && rdb.meshes[i].twoSided) {
      // A two-sided mesh baked one-sided (no back values) shows its front values on both faces.
      const bool front = maps[i]->backLux.empty();
      place(rdb.backLux, front ? maps[i]->frontLux : maps[i]->backLux, i);
      if (sunDirect)
        place(rdb.backSunDirectLux, front ? maps[i]->frontSunDirectLux : maps[i]->backSunDirectLux, i);
    }
  }
  if (!rdb.lightTextures.empty()) {
    rdb.lightMapUv.assign(rdb.positionsM.size(), vec2(0.0f));
    for (size_t i = 0; i < meshUv.size(); ++i)
      std::copy(meshUv[i].begin(), meshUv[i].end(), rdb.lightMapUv.begin() + rdb.meshes[i].firstVertex);
  }
}

// The corner factor of the directional ambient term (raster_rdb.h). Points closer than 10⁻⁵ of the scene's
// diagonal are welded (quantised), so meshes that meet (walls, floor, ceiling) form one corner.
void buildCornerFactors(RasterRdb& rdb) {
  const size_t nv = rdb.positionsM.size();
  rdb.cornerFactor.assign(nv, 0.0f);
  if (nv == 0) return;
  const double quantumM = std::max(1e-6, 1e-5 * double(glm::length(rdb.boundsM.size())));
  struct Key {
    int64_t x, y, z;
    bool operator==(const Key&) const = default;
  };
  struct KeyHash {
    size_t operator()(const Key& k) const {
      return size_t(k.x * 73856093LL) ^ size_t(k.y * 19349663LL) ^ size_t(k.z * 83492791LL);
    }
  };
  auto key = [&](const vec3& p) {
    return Key{int64_t(std::llround(p.x / quantumM)), int64_t(std::llround(p.y / quantumM)),
               int64_t(std::llround(p.z / quantumM))};
  };
  std::unordered_map<Key, uint32_t, KeyHash> groupOf;
  std::vector<uint32_t> vertexGroup(nv);
  for (size_t v = 0; v < nv; ++v) {
    vertexGroup[v] = groupOf.try_emplace(key(rdb.positionsM[v]), uint32_t(groupOf.size())).first->second;
  }
  struct Acc {
    dvec3 normalSum{0.0};  // Σ wᵢ nᵢ
    double weight = 0.0;   // Σ wᵢ
    dvec3 edgeSum{0.0};    // Σ of unit edge directions away from the point
    dvec3 position{0.0};
  };
  std::vector<Acc> acc(groupOf.size());
  for (size_t t = 0; t + 2 < rdb.indices.size(); t += 3) {
    const uint32_t* v = &rdb.indices[t];
    const dvec3 p[3] = {dvec3(rdb.positionsM[v[0]]), dvec3(rdb.positionsM[v[1]]),
                        dvec3(rdb.positionsM[v[2]])};
    const std::optional<vec3> n = unitOrNone(glm::cross(p[1] - p[0], p[2] - p[0]));
    if (!n) continue;
    for (int k = 0; k < 3; ++k) {
      const std::optional<vec3> a = unitOrNone(p[(k + 1) % 3] - p[k]);
      const std::optional<vec3> b = unitOrNone(p[(k + 2) % 3] - p[k]);
      if (!a || !b) continue;
      const double angle = std::acos(std::clamp(double(glm::dot(*a, *b)), -1.0, 1.0));
      Acc& g = acc[vertexGroup[v[k]]];
      g.normalSum += angle * dvec3(*n);
      g.weight += angle;
      g.edgeSum += dvec3(*a) + dvec3(*b);
    }
  }
  for (size_t v = 0; v < nv; ++v) {
    const Acc& g = acc[vertexGroup[v]];
    if (!(g.weight > 0.0)) continue;
    const double spread = 1.0 - glm::length(g.normalSum) / g.weight;
    // Concave: the edges leaving the point rise along the mean normal (a room's corner); convex corners (a
    // box's outside) get nothing.
    const bool concave = glm::dot(g.edgeSum, g.normalSum) > 1e-6 * g.weight;
    rdb.cornerFactor[v] = concave ? float(std::clamp(spread, 0.0, 1.0)) : 0.0f;
  }
}

// Material table: index 0 the default material, then the meshes' materials in first-use order. Returns the
// texture table's keys in the order the materials first use them.
std::vector<TextureKey> buildMaterials(RasterRdb& rdb, const sdb::Scene& scene) {
  TextureTable table;
  rdb.materials.clear();
  rdb.materials.push_back(lowerRasterMaterial(scene.material(sdb::MaterialId{}), 0, table));
  std::map<uint32_t, uint32_t> index{{0u, 0u}};
  for (RasterMesh& rm : rdb.meshes) {
    const sdb::MaterialId id = scene.mesh(sdb::MeshId{rm.sdbMeshId}).material;
    const auto [it, added] = index.try_emplace(id.value, uint32_t(rdb.materials.size()));
    if (added) rdb.materials.push_back(lowerRasterMaterial(scene.material(id), id.value, table));
    rm.material = it->second;
  }
  return table.keys;
}

// The measured BRDFs of the materials that have one (after buildMaterials), each with the bounding box of the
// meshes that use it. Such a material's block keeps only its emission and coverage, and as its diffuse albedo
// the BRDF's albedo at (nearly) normal incidence.
void buildMeasuredBrdfs(RasterRdb& rdb, const sdb::Scene& scene) {
  rdb.measuredBrdfs.clear();
  for (uint32_t i = 0; i < rdb.materials.size(); ++i) {
    RasterMaterial& block = rdb.materials[i];
    const sdb::Material& m = scene.material(sdb::MaterialId{block.sdbMaterialId});
    if (!m.isMeasured() || block.transmission != Rgb(0.0f)) continue;
    RasterMeasuredBrdf brdf = lowerMeasuredBrdf(m, block.sdbMaterialId);
    Bounds3 b;
    for (const RasterMesh& mesh : rdb.meshes) {
      if (mesh.material != i) continue;
      for (uint32_t v = mesh.firstVertex; v < mesh.firstVertex + mesh.vertexCount; ++v) b.extend(rdb.positionsM[v]);
    }
    if (!b.empty()) {
      brdf.centreM = 0.5f * (b.min + b.max);
      brdf.radiusM = 0.5f * glm::length(b.size());
    }
    block.measured = uint32_t(rdb.measuredBrdfs.size());
    block.diffuse = glm::clamp(brdf.albedo.back(), Rgb(0.0f), Rgb(1.0f));
    block.specular = Rgb(0.0f);
    block.reflection = Rgb(0.0f);
    block.environmentF90 = Rgb(0.0f);
    rdb.measuredBrdfs.push_back(std::move(brdf));
  }
}

bool anyMeasured(const RasterRdb& rdb) { return !rdb.measuredBrdfs.empty(); }

void buildTextures(RasterRdb& rdb, const sdb::Scene& scene, const std::vector<TextureKey>& keys) {
  rdb.textures.clear();
  for (const TextureKey& k : keys) rdb.textures.push_back(lowerTexture(scene, k));
}

std::vector<TextureKey> textureKeys(const RasterRdb& rdb) {
  std::vector<TextureKey> keys;
  for (const RasterTexture& t : rdb.textures) keys.push_back({t.sdbTextureId, t.srgb});
  return keys;
}

bool anyAlphaOrTexture(const RasterRdb& rdb) {
  return !rdb.textures.empty() || std::any_of(rdb.materials.begin(), rdb.materials.end(), [](const RasterMaterial& m) {
           return m.alphaMode != RasterAlphaMode::kOpaque;
         });
}

void buildLights(RasterRdb& rdb, const sdb::Scene& scene) {
  rdb.lights.clear();
  rdb.goniometricCd.clear();
  scene.forEachNode([&](sdb::NodeId nodeId, const mat4& worldFromLocal) {
    const sdb::Node& node = scene.node(nodeId);
    if (!node.light) return;
    const sdb::Light& light = scene.light(node.light);
    RasterLight r;
    r.sdbLightId = node.light.value;
    const LightFrame frame = placeLight(scene, node, worldFromLocal);
    r.positionM = frame.positionM;
    r.directionWorld = frame.directionWorld;
    r.cAxisWorld = frame.cAxisWorld;
    r.intensity = light.color * light.intensity;
    r.rangeM = light.rangeM;
    switch (light.type) {
      case sdb::LightType::kPoint:
        r.type = RasterLightType::kPoint;
        break;
      case sdb::LightType::kDirectional:
        r.type = RasterLightType::kDirectional;
        break;
      case sdb::LightType::kSpot:
        r.type = RasterLightType::kSpot;
        r.cosInner = std::cos(light.innerConeRad);
        r.cosOuter = std::cos(light.outerConeRad);
        break;
      case sdb::LightType::kGoniometric: {
        r.type = RasterLightType::kGoniometric;
        r.goniometricOffset = uint32_t(rdb.goniometricCd.size());
        const TraceGoniometricTable t =
            tabulateGoniometric(*light.ies, kRasterGonioGammaSteps, kRasterGonioCSteps);
        rdb.goniometricCd.insert(rdb.goniometricCd.end(), t.candelaCd.begin(), t.candelaCd.end());
        break;
      }
    }
    rdb.lights.push_back(r);
  });
}

// The goniometric table's intensity towards `toSurface` (unit, light frame in world axes), bilinear; the same
// lookup as the shader's flyGonioCd.
float gonioCd(const RasterRdb& rdb, const RasterLight& l, const vec3& toSurface) {
  const vec3 yAxis = glm::cross(l.directionWorld, l.cAxisWorld);
  const float cosG = std::clamp(glm::dot(toSurface, l.directionWorld), -1.0f, 1.0f);
  const float gamma = std::acos(cosG) / kPiF * float(kRasterGonioGammaSteps - 1);
  float c = std::atan2(glm::dot(toSurface, yAxis), glm::dot(toSurface, l.cAxisWorld)) / (2.0f * kPiF);
  if (c < 0.0f) c += 1.0f;
  c *= float(kRasterGonioCSteps);
  const uint32_t g0 = std::min(uint32_t(gamma), kRasterGonioGammaSteps - 2);
  const float fg = std::clamp(gamma - float(g0), 0.0f, 1.0f);
  const uint32_t c0 = std::min(uint32_t(c), kRasterGonioCSteps - 1);
  const uint32_t c1 = (c0 + 1) % kRasterGonioCSteps;
  const float fc = std::clamp(c - float(c0), 0.0f, 1.0f);
  const float* t = rdb.goniometricCd.data() + l.goniometricOffset;
  auto at = [&](uint32_t ci, uint32_t gi) { return t[ci * kRasterGonioGammaSteps + gi]; };
  return (1 - fc) * ((1 - fg) * at(c0, g0) + fg * at(c0, g0 + 1)) +
         fc * ((1 - fg) * at(c1, g0) + fg * at(c1, g0 + 1));
}

// Unshadowed direct illuminance (lux) from one light at a point with unit normal n.
Rgb directIlluminanceLux(const RasterRdb& rdb, const RasterLight& l, const vec3& p, const vec3& n) {
  vec3 toLight;
  const Rgb e = punctualIlluminanceLux(rdb, l, p, toLight);
  return e * std::max(0.0f, glm::dot(n, toLight));
}

// Rays from the scene's surfaces for its closure (RasterRdb::ambientClosure): at most kClosureRays, and
// at most kClosureRayTests ray–triangle tests in all (each ray may test every triangle), but at least
// kMinClosureRays.
constexpr uint32_t kClosureRays = 4096;
constexpr uint32_t kMinClosureRays = 32;
constexpr double kClosureRayTests = 3.0e7;

// Whether the ray o + t d, t in (tMinM, ∞), meets any triangle (Möller & Trumbore 1997, either face).
bool hitsAnyTriangle(const RasterRdb& rdb, const dvec3& o, const dvec3& d, double tMinM) {
  for (size_t i = 0; i + 2 < rdb.indices.size(); i += 3) {
    const dvec3 p0(rdb.positionsM[rdb.indices[i]]);
    const dvec3 e1 = dvec3(rdb.positionsM[rdb.indices[i + 1]]) - p0, e2 = dvec3(rdb.positionsM[rdb.indices[i + 2]]) - p0;
    const dvec3 pv = glm::cross(d, e2);
    const double det = glm::dot(e1, pv);
    if (!(std::abs(det) > 1e-14 * glm::length(e1) * glm::length(e2))) continue;
    const double inv = 1.0 / det;
    const dvec3 tv = o - p0;
    const double u = glm::dot(tv, pv) * inv;
    if (u < 0.0 || u > 1.0) continue;
    const dvec3 qv = glm::cross(tv, e1);
    const double v = glm::dot(d, qv) * inv;
    if (v < 0.0 || u + v > 1.0) continue;
    if (glm::dot(e2, qv) * inv > tMinM) return true;
  }
  return false;
}

// The scene's closure (RasterRdb::ambientClosure): rays from points on the faces that send light out (the
// front of one-sided meshes, both faces of two-sided ones), each face chosen by `faceWeight(first index,
// back)` (its flux: what it emits and what it reflects of the lights) and the point uniform on it,
// cosine-distributed about the face's normal, that meet another triangle. Deterministic: points and
// directions from a Halton sequence (bases 2, 3, 5, 7, 11) by the ray's index.
template <class FaceWeight>
float estimateClosure(const RasterRdb& rdb, const FaceWeight& faceWeight) {
  std::vector<double> cdf;
  std::vector<uint32_t> faceOf;  // per cdf entry: the triangle's first index, times 2, plus 1 for its back
  double sum = 0.0;
  for (const RasterMesh& m : rdb.meshes) {
    for (uint32_t i = m.firstIndex; i + 2 < m.firstIndex + m.indexCount; i += 3) {
      for (uint32_t side = 0; side < (m.twoSided ? 2u : 1u); ++side) {
        const double w = faceWeight(i, side == 1);
        if (!(w > 0.0)) continue;
        sum += w;
        cdf.push_back(sum);
        faceOf.push_back(2 * i + side);
      }
    }
  }
  if (cdf.empty()) return 0.0f;
  const double triangles = double(rdb.indices.size() / 3);
  const uint32_t rays =
      uint32_t(std::clamp(kClosureRayTests / triangles, double(kMinClosureRays), double(kClosureRays)));
  auto halton = [](uint32_t index, uint32_t base) {
    double f = 1.0, r = 0.0;
    for (uint32_t i = index; i > 0; i /= base) {
      f /= double(base);
      r += f * double(i % base);
    }
    return r;
  };
  const dvec3 extent = dvec3(rdb.boundsM.max) - dvec3(rdb.boundsM.min);
  const double tMinM = 1e-6 * std::max(glm::length(extent), 1e-3);
  uint32_t hits = 0;
  for (uint32_t k = 0; k < rays; ++k) {
    const uint32_t index = k + 1;
    const double pick = halton(index, 2) * sum;
    const size_t e = std::min(size_t(std::upper_bound(cdf.begin(), cdf.end(), pick) - cdf.begin()), cdf.size() - 1);
    const uint32_t i = faceOf[e] / 2;
    const bool back = (faceOf[e] & 1u) != 0u;
    const dvec3 p0(rdb.positionsM[rdb.indices[i]]), p1(rdb.positionsM[rdb.indices[i + 1]]),
        p2(rdb.positionsM[rdb.indices[i + 2]]);
    // A uniform point of the triangle (square-root warp) and a cosine-distributed direction about its normal.
    const double su = std::sqrt(halton(index, 3)), v = halton(index, 5);
    const dvec3 p = (1.0 - su) * p0 + su * (1.0 - v) * p1 + su * v * p2;
    dvec3 n = glm::normalize(glm::cross(p1 - p0, p2 - p0));
    if (back) n = -n;
    const double r = std::sqrt(halton(index, 7)), phi = 2.0 * kPi * halton(index, 11);
    const dvec3 t = glm::normalize(std::abs(n.x) > 0.5 ? glm::cross(n, dvec3(0, 1, 0)) : glm::cross(n, dvec3(1, 0, 0)));
    const dvec3 b = glm::cross(n, t);
    const dvec3 d = glm::normalize(r * std::cos(phi) * t + r * std::sin(phi) * b + std::sqrt(std::max(0.0, 1.0 - r * r)) * n);
    hits += hitsAnyTriangle(rdb, p + tMinM * n, d, tMinM) ? 1u : 0u;
  }
  return float(double(hits) / double(rays));
}

// The simple mode's ambient term (raster_rdb.h): the daylight's (buildSky first) plus progressive radiosity's
// for the scene's lights and its emissive surfaces.
void buildAmbient(RasterRdb& rdb) {
  rdb.ambient = rdb.daylightAmbient;
  rdb.ambientClosure.reset();
  if (rdb.indices.empty()) return;
  // Per triangle (by its first index / 3): area, and the luminous flux its faces send out — what they emit
  // and what they reflect of the lights' unshadowed direct light (ρ · Ē over its corners, front and, for
  // two-sided meshes, back).
  const size_t triangles = rdb.indices.size() / 3;
  std::vector<double> area(triangles, 0.0), frontOut(triangles, 0.0), backOut(triangles, 0.0);
  std::vector<double> vertexArea(rdb.positionsM.size(), 0.0);
  double areaSum = 0.0, albedoSum = 0.0;
  dvec3 emittedLm(0.0);
  for (const RasterMesh& rm : rdb.meshes) {
    const RasterMaterial& material = rdb.materials[rm.material];
    const float albedo = luminance(material.diffuse);
    for (uint32_t i = rm.firstIndex; i + 2 < rm.firstIndex + rm.indexCount; i += 3) {
      const uint32_t* v = &rdb.indices[i];
      const double a =
          0.5 * glm::length(glm::cross(dvec3(rdb.positionsM[v[1]]) - dvec3(rdb.positionsM[v[0]]),
                                       dvec3(rdb.positionsM[v[2]]) - dvec3(rdb.positionsM[v[0]])));
      for (int k = 0; k < 3; ++k) vertexArea[v[k]] += a / 3.0;
      areaSum += a;
      albedoSum += a * albedo;
      // A Lambertian emitter of luminance L sends π·L lm/m² from each emitting face.
      // A display colour (emissionDisplay) lights nothing.
      const Rgb emission = material.emissionDisplay ? Rgb(0.0f) : material.emissionCdM2;
      const double emitted = kPi * a * double(luminance(emission));
      emittedLm += kPi * (rm.twoSided ? 2.0 : 1.0) * a * dvec3(emission);
      double eFront = 0.0, eBack = 0.0;
      for (int k = 0; k < 3 && !rdb.lights.empty(); ++k) {
        for (const RasterLight& l : rdb.lights) {
          eFront += luminance(directIlluminanceLux(rdb, l, rdb.positionsM[v[k]], rdb.normals[v[k]])) / 3.0;
          if (rm.twoSided)
            eBack += luminance(directIlluminanceLux(rdb, l, rdb.positionsM[v[k]], -rdb.normals[v[k]])) / 3.0;
        }
      }
      area[i / 3] = a;
      frontOut[i / 3] = emitted + albedo * eFront * a;
      backOut[i / 3] = rm.twoSided ? emitted + albedo * eBack * a : 0.0;
    }
  }
  if (!(areaSum > 0.0)) return;
  if (rdb.lights.empty() && !(maxComponent(emittedLm) > 0.0)) return;  // no term of progressive radiosity
  rdb.ambientClosure = estimateClosure(rdb, [&](uint32_t first, bool back) {
    return back ? backOut[first / 3] : frontOut[first / 3];
  });
  const double rho = std::min(0.9, albedoSum / areaSum);
  const double c = *rdb.ambientClosure;
  dvec3 level = emittedLm / areaSum * (c / (1.0 - rho * c));
  if (!rdb.lights.empty()) {
    dvec3 eSum(0.0);
    for (size_t v = 0; v < rdb.positionsM.size(); ++v) {
      if (vertexArea[v] == 0.0) continue;
      Rgb e(0.0f);
      for (const RasterLight& l : rdb.lights)
        e += directIlluminanceLux(rdb, l, rdb.positionsM[v], rdb.normals[v]);
      eSum += vertexArea[v] * dvec3(e);
    }
    level += eSum / areaSum * (rho * c / (1.0 - rho * c));
  }
  rdb.ambient.upLux += Rgb(level);
  rdb.ambient.downLux += Rgb(level);
}

void buildSky(RasterRdb& rdb, const sdb::Scene& scene, const RasterBuildOptions& options) {
  rdb.sky = buildRasterSky(scene, options.skyWidth, options.skyHeight);
  rdb.daylightAmbient = DirectionalAmbient{};
  if (!rdb.sky) return;
  const RasterSky& s = *rdb.sky;
  // Horizontal illuminance of the upper hemisphere: Σ L · ∫ cos θ dω over each pixel, exactly
  // Δφ · (sin²θ₁ − sin²θ₀) / 2 for the rows above the horizon.
  dvec3 eSky(0.0);
  const double dPhi = 2.0 * kPi / s.width;
  for (uint32_t j = 0; j < s.height; ++j) {
    const double t0 = kPi * j / s.height;
    const double t1 = std::min(kPi / 2.0, kPi * (j + 1) / s.height);
    if (t0 >= kPi / 2.0) break;
    const double w = dPhi * 0.5 * (std::sin(t1) * std::sin(t1) - std::sin(t0) * std::sin(t0));
    for (uint32_t i = 0; i < s.width; ++i) eSky += w * dvec3(s.radianceCdM2[size_t(j) * s.width + i]);
  }
  dvec3 eSunHorizontal(0.0);
  if (s.hasSun) {
    const double solidAngle = 2.0 * kPi * (1.0 - std::cos(double(s.sunHalfAngleRad)));
    eSunHorizontal = dvec3(s.sunRadianceCdM2) * solidAngle * std::max(0.0, double(s.sunDirWorld.y));
  }
  rdb.daylightAmbient.upLux = Rgb(eSky);
  rdb.daylightAmbient.downLux = Rgb(double(s.groundAlbedo) * (eSky + eSunHorizontal));
}

void buildCameras(RasterRdb& rdb, const sdb::Scene& scene) {
  rdb.cameras.clear();
  std::map<uint32_t, RasterCamera> byId;
  scene.forEachNode([&](sdb::NodeId nodeId, const mat4& worldFromLocal) {
    const sdb::Node& node = scene.node(nodeId);
    if (!node.camera || byId.count(node.camera.value)) return;
    const sdb::Camera& c = scene.camera(node.camera);
    RasterCamera r;
    r.name = c.name;
    r.sdbCameraId = node.camera.value;
    r.sdbNodeId = nodeId.value;
    // Rigid part of the placement: orthonormalised axes (a scaled node does not scale the view).
    const vec3 z = unitOrNone(dvec3(worldFromLocal[2])).value_or(vec3(0, 0, 1));
    const vec3 x = unitOrNone(dvec3(glm::cross(vec3(worldFromLocal[1]), z))).value_or(vec3(1, 0, 0));
    const vec3 y = glm::cross(z, x);
    r.worldFromCamera = frameTransform(x, y, z, vec3(worldFromLocal[3]));
    r.projection = c.projection == sdb::Projection::kOrthographic ? RasterProjection::kOrthographic
                                                                  : RasterProjection::kPerspective;
    r.yfovRad = c.yfovRad;
    r.aspectRatio = c.aspectRatio;
    r.znearM = c.znearM;
    r.zfarM = c.zfarM;
    r.xmagM = c.xmagM;
    r.ymagM = c.ymagM;
    byId.emplace(r.sdbCameraId, std::move(r));
  });
  for (auto& [id, c] : byId) rdb.cameras.push_back(std::move(c));
}

// The flat meshes of mirror materials, grouped by material and plane (RasterPlanarReflector), the
// kMaxPlanarReflectors largest kept; each mesh's planarReflector set (none for the rest).
// The curved meshes of mirror-like materials and every mesh of "cubemap" ones: RasterCubeReflector, the
// kMaxCubeReflectors largest kept; each mesh's cubeReflector set (none for the rest).
void buildCubeReflectors(RasterRdb& rdb, const std::vector<char>& flat) {
  std::vector<RasterCubeReflector> all;
  for (uint32_t i = 0; i < rdb.meshes.size(); ++i) {
    RasterMesh& mesh = rdb.meshes[i];
    mesh.cubeReflector = RasterTextureRef::kNone;
    const RasterMaterial& m = rdb.materials[mesh.material];
    if (mesh.indexCount == 0 || mesh.planarReflector != RasterTextureRef::kNone) continue;
    if (!m.cubeMapAlways && !(m.cubeMapOnCurved && !flat[i])) continue;
    Bounds3 b;
    for (uint32_t v = mesh.firstVertex; v < mesh.firstVertex + mesh.vertexCount; ++v) b.extend(rdb.positionsM[v]);
    all.push_back({mesh.material, i, 0.5f * (b.min + b.max), 0.5f * glm::length(b.size())});
  }
  std::stable_sort(all.begin(), all.end(), [](const auto& a, const auto& b) { return a.radiusM > b.radiusM; });
  if (all.size() > kMaxCubeReflectors) all.resize(kMaxCubeReflectors);
  for (uint32_t k = 0; k < all.size(); ++k) rdb.meshes[all[k].mesh].cubeReflector = k;
  rdb.cubeReflectors = std::move(all);
}

// Returns per mesh whether it is flat (for buildCubeReflectors).
std::vector<char> buildPlanarReflectors(RasterRdb& rdb) {
  std::vector<RasterPlanarReflector> all;
  std::vector<char> flatMeshes(rdb.meshes.size(), 0);
  for (uint32_t i = 0; i < rdb.meshes.size(); ++i) {
    RasterMesh& mesh = rdb.meshes[i];
    mesh.planarReflector = RasterTextureRef::kNone;
    const RasterMaterial& material = rdb.materials[mesh.material];
    if (!(material.mirrorLike || material.cubeMapOnCurved) || mesh.indexCount == 0) continue;
    // The area-weighted normal, the area and the extent; flat when every vertex lies on its plane.
    vec3 weighted(0.0f);
    double area = 0.0;
    Bounds3 b;
    for (uint32_t k = mesh.firstIndex; k + 2 < mesh.firstIndex + mesh.indexCount; k += 3) {
      const vec3& p0 = rdb.positionsM[rdb.indices[k]];
      const vec3 c = glm::cross(rdb.positionsM[rdb.indices[k + 1]] - p0, rdb.positionsM[rdb.indices[k + 2]] - p0);
      weighted += c;
      area += 0.5 * glm::length(c);
    }
    if (!(glm::length(weighted) > 0.0f)) continue;
    const vec3 normal = glm::normalize(weighted);
    double centre = 0.0;
    for (uint32_t v = mesh.firstVertex; v < mesh.firstVertex + mesh.vertexCount; ++v) {
      b.extend(rdb.positionsM[v]);
      centre += glm::dot(normal, rdb.positionsM[v]);
    }
    const float offset = float(centre / mesh.vertexCount);
    const float tolerance = std::max(1e-3f, 1e-4f * glm::length(b.size()));
    bool flat = true;
    for (uint32_t v = mesh.firstVertex; v < mesh.firstVertex + mesh.vertexCount && flat; ++v)
      flat = std::abs(glm::dot(normal, rdb.positionsM[v]) - offset) <= tolerance;
    flatMeshes[i] = flat ? 1 : 0;
    if (!flat || !material.mirrorLike) continue;
    auto same = [&](const RasterPlanarReflector& r) {
      return r.material == mesh.material && glm::dot(r.normal, normal) > 0.9999995f &&
             std::abs(r.offsetM - offset) <= 1e-3f;
    };
    auto it = std::find_if(all.begin(), all.end(), same);
    if (it == all.end()) it = all.insert(all.end(), RasterPlanarReflector{normal, offset, mesh.material, {}, 0.0f, b.min, b.max});
    it->meshes.push_back(i);
    it->areaM2 += float(area);
    it->loM = glm::min(it->loM, b.min);
    it->hiM = glm::max(it->hiM, b.max);
  }
  std::stable_sort(all.begin(), all.end(), [](const auto& a, const auto& b) { return a.areaM2 > b.areaM2; });
  if (all.size() > kMaxPlanarReflectors) all.resize(kMaxPlanarReflectors);
  for (uint32_t k = 0; k < all.size(); ++k)
    for (uint32_t i : all[k].meshes) rdb.meshes[i].planarReflector = k;
  rdb.planarReflectors = std::move(all);
  return flatMeshes;
}

void buildVariants(RasterRdb& rdb, const sdb::Scene& scene) {
  const sdb::SceneFeatures f = sdb::computeFeatures(scene);
  rdb.variants.lightMap = !rdb.frontLux.empty();
  rdb.variants.lightTexture = !rdb.lightTextures.empty();
  rdb.variants.sunDirect = !rdb.frontSunDirectLux.empty();
  rdb.variants.twoSided =
      std::any_of(rdb.meshes.begin(), rdb.meshes.end(), [](const RasterMesh& m) { return m.twoSided; });
  rdb.variants.sky = rdb.sky.has_value();
  rdb.variants.sun = rdb.sky && rdb.sky->hasSun;
  rdb.variants.goniometric = f.goniometricLights && !rdb.goniometricCd.empty();
  rdb.variants.glass = std::any_of(rdb.meshes.begin(), rdb.meshes.end(), [&](const RasterMesh& m) {
    return maxComponent(rdb.materials[m.material].transmission) > 0.0f;
  });
  rdb.variants.diffuseByAngle = std::any_of(rdb.meshes.begin(), rdb.meshes.end(), [&](const RasterMesh& m) {
    const RasterMaterial& x = rdb.materials[m.material];
    for (int c = 0; c < 3; ++c)
      if (x.specular[c] < 1.0f && x.environmentF90[c] != x.specular[c]) return true;
    return false;
  });
  rdb.variants.frostedGlass = std::any_of(rdb.meshes.begin(), rdb.meshes.end(), [&](const RasterMesh& m) {
    const RasterMaterial& x = rdb.materials[m.material];
    return maxComponent(x.transmission) > 0.0f && x.transmissionAlpha > 0.0f;
  });
  RasterVariants& v = rdb.variants;
  v.textures = v.normalMaps = v.anisotropy = v.glossinessTextures = v.metalnessTextures = v.uv1 =
      v.vertexColors = v.alphaMask = v.alphaBlend = false;
  for (const RasterMesh& mesh : rdb.meshes) {
    const RasterMaterial& m = rdb.materials[mesh.material];
    v.textures |= m.hasTexture();
    v.normalMaps |= bool(m.normalTexture);
    v.anisotropy |= m.anisotropic;
    v.glossinessTextures |= bool(m.glossinessTexture);
    v.metalnessTextures |= bool(m.metalnessTexture);
    for (const RasterTextureRef* t :
         {&m.baseColorTexture, &m.emissionTexture, &m.normalTexture, &m.anisotropyTexture,
          &m.anisotropyRotationTexture, &m.glossinessTexture, &m.transmissionTexture, &m.metalnessTexture})
      v.uv1 |= bool(*t) && t->texCoord == 1;
    v.vertexColors |= mesh.hasColors;
    v.alphaMask |= m.alphaMode == RasterAlphaMode::kMask;
    v.alphaBlend |= m.alphaMode == RasterAlphaMode::kBlend;
    v.reflectionFog |= m.hasReflectionFog();
  }
  v.measuredBrdf = !rdb.measuredBrdfs.empty();
  v.planarReflectors = !rdb.planarReflectors.empty();
  v.cubeReflectors = !rdb.cubeReflectors.empty();
}

void checkOptions(const RasterBuildOptions& o) {
  if (o.skyWidth < 1 || o.skyHeight < 1 || o.skyWidth > 8192 || o.skyHeight > 8192) {
    throw std::invalid_argument("buildRasterRdb: sky image size out of range ([1, 8192] pixels per side)");
  }
}

}  // namespace

RasterRdb buildRasterRdb(const sdb::Scene& scene, const LightMapStore* lightMaps,
                         const RasterBuildOptions& options) {
  checkOptions(options);
  RasterRdb rdb;
  buildGeometry(rdb, scene, lightMaps);
  buildCornerFactors(rdb);
  buildTextures(rdb, scene, buildMaterials(rdb, scene));
  buildMeasuredBrdfs(rdb, scene);
  buildLights(rdb, scene);
  buildSky(rdb, scene, options);
  buildAmbient(rdb);
  buildCameras(rdb, scene);
  buildCubeReflectors(rdb, buildPlanarReflectors(rdb));
  buildVariants(rdb, scene);
  return rdb;
}

RasterRdbChanges updateRasterRdb(RasterRdb& rdb, const sdb::Scene& scene, const sdb::ChangeSet& changes,
                                 const LightMapStore* lightMaps, const RasterBuildOptions& options) {
  checkOptions(options);
  RasterRdbChanges r;
  std::vector<uint32_t> editedMaterials;
  for (const sdb::Change& c : changes.changes) {
    switch (c.type) {
      case sdb::EntityType::kNode:
        r.geometry = true;
        break;
      case sdb::EntityType::kMesh:
        if (c.kind == sdb::ChangeKind::kModified && c.aspect == sdb::Aspect::kMaterialAssignment) {
          r.materials = true;
        } else {
          r.geometry = true;
        }
        break;
      case sdb::EntityType::kMaterial:
        if (c.kind != sdb::ChangeKind::kAdded)
          editedMaterials.push_back(c.id);  // an added one is not used yet
        break;
      case sdb::EntityType::kLight:
        r.lights = true;
        break;
      case sdb::EntityType::kCamera:
        r.cameras = true;
        break;
      case sdb::EntityType::kSite:
      case sdb::EntityType::kTime:
      case sdb::EntityType::kSky:
        r.sky = true;
        break;
      case sdb::EntityType::kTexture:  // other pixels: the texture table (an added one is not used yet)
        if (c.kind != sdb::ChangeKind::kAdded) r.geometry = true;
        break;
      case sdb::EntityType::kBake:
      case sdb::EntityType::kPortals:  // no geometry: the GL engine draws no portal
        break;
    }
  }
  const auto rebuild = [&] {
    rdb = buildRasterRdb(scene, lightMaps, options);
    return RasterRdbChanges{true, true, {}, true, true, true, true};
  };
  if (r.geometry) return rebuild();
  if (r.materials) {
    // An assignment may change the textures, attributes and draws the scene needs: rebuilt wherever
    // textures or coverage are involved before or after.
    const bool before = anyAlphaOrTexture(rdb) || anyMeasured(rdb);
    const std::vector<TextureKey> keys = buildMaterials(rdb, scene);
    buildMeasuredBrdfs(rdb, scene);
    if (before || !keys.empty() || anyAlphaOrTexture(rdb) || anyMeasured(rdb)) return rebuild();
  } else {
    // The texture table in order, for the edited blocks to find their textures in (lookup only).
    TextureTable table{textureKeys(rdb), false, false};
    for (uint32_t id : editedMaterials) {
      for (uint32_t i = 0; i < rdb.materials.size(); ++i) {
        if (rdb.materials[i].sdbMaterialId != id) continue;
        // A measured BRDF's table, ball and draws: rebuilt when one is involved before or after.
        if (rdb.materials[i].measured != RasterTextureRef::kNone || scene.material(sdb::MaterialId{id}).isMeasured())
          return rebuild();
        const RasterMaterial block = lowerRasterMaterial(scene.material(sdb::MaterialId{id}), id, table);
        // Other textures, UV sets or alpha mode: other tables, attributes and draws.
        if (table.missing || !sameTextureLayout(block, rdb.materials[i])) return rebuild();
        rdb.materials[i] = block;
        r.materialBlocks.push_back(i);
      }
    }
  }
  if (r.lights) buildLights(rdb, scene);
  if (r.sky) buildSky(rdb, scene, options);
  if (r.materials || !r.materialBlocks.empty() || r.lights || r.sky) {
    buildAmbient(rdb);
    r.ambient = true;
  }
  if (r.cameras) buildCameras(rdb, scene);
  if (r.lights || r.sky || r.materials || !r.materialBlocks.empty()) buildVariants(rdb, scene);
  return r;
}

Rgb punctualIlluminanceLux(const RasterRdb& rdb, const RasterLight& l, const vec3& p, vec3& toLightWorld) {
  if (l.type == RasterLightType::kDirectional) {
    toLightWorld = -l.directionWorld;
    return l.intensity;
  }
  toLightWorld = vec3(0.0f, 0.0f, 1.0f);
  const vec3 d = l.positionM - p;
  const float dist2 = glm::dot(d, d);
  if (!(dist2 > 1e-12f)) return Rgb(0.0f);
  const float dist = std::sqrt(dist2);
  toLightWorld = d / dist;
  float window = 1.0f;
  if (std::isfinite(l.rangeM)) {
    const float r = dist / l.rangeM;
    window = std::max(0.0f, 1.0f - r * r * r * r);  // KHR_lights_punctual: clamp(1 − (d/range)⁴, 0, 1) / d²
  }
  float cd = 1.0f;
  if (l.type == RasterLightType::kSpot) {
    cd = spotConeAttenuation(glm::dot(-toLightWorld, l.directionWorld), l.cosInner, l.cosOuter);
  } else if (l.type == RasterLightType::kGoniometric) {
    cd = gonioCd(rdb, l, -toLightWorld);
  }
  return l.intensity * (cd * window / dist2);
}

}  // namespace fly::rdb
