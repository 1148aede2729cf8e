#include "rdb/trace_rdb_build.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "base/error.h"
#include "base/log.h"
#include "rdb/lightmap_uv.h"
#include "rdb/placed_mesh.h"
#include "rdb/site_lowering.h"
#include "rdb/vertex_weld.h"

namespace fly::rdb {

// Generated light-map UVs for mesh tm of rdb into lt: charts over its triangles with coincident vertices of
// equal normals welded (rdb/vertex_weld.h), so that faces written with vertices of their own chart together.
// Unless allCharts, a chart whose triangles are at least as dense as its texels would be (fewer than
// kMinTexelsPerTriangle texels per triangle: a curved detail, a bevel, a finely tessellated patch) is left
// out of the atlas: its vertex light maps carry its light at least as finely, and a texel would average over
// its differently turned triangles. Its corners get noLightTextureUv(); when every chart is left out, lt's
// atlas is 0 × 0.
static void generateAtlas(const TraceRdb& rdb, const TraceMesh& tm, float texelsPerMetre, int maxSize,
                            int paddingTexels, bool allCharts, TraceLightTexture& lt) {
  const std::span<const vec3> positions = std::span<const vec3>(rdb.positionsM).subspan(tm.firstVertex, tm.vertexCount);
  const std::span<const vec3> normals = std::span<const vec3>(rdb.normals).subspan(tm.firstVertex, tm.vertexCount);
  Bounds3 bounds;
  for (const vec3& p : positions) bounds.extend(p);
  const std::vector<uint32_t> weld =
      weldCoincidentVertices(positions, normals, weldToleranceM(glm::length(bounds.max - bounds.min)));
  const uint32_t* corners = rdb.indices.data() + 3 * size_t(tm.firstTriangle);
  std::vector<uint32_t> local(corners, corners + 3 * size_t(tm.triangleCount));
  for (uint32_t& i : local) i = weld[i - tm.firstVertex];
  const LightmapUvSettings settings{
      .texelsPerMetre = texelsPerMetre, .paddingTexels = paddingTexels, .maxAtlasSize = maxSize};
  auto areaM2 = [&](size_t k) {
    const dvec3 p0(positions[local[3 * k]]);
    return 0.5 * glm::length(glm::cross(dvec3(positions[local[3 * k + 1]]) - p0, dvec3(positions[local[3 * k + 2]]) - p0));
  };
  std::vector<uint8_t> keep(tm.triangleCount, 1);
  if (!allCharts) {
    const LightmapUv charts = generateLightmapUv(positions, local, settings);
    std::vector<double> chartArea(charts.chartCount, 0.0);
    std::vector<size_t> chartTriangles(charts.chartCount, 0);
    for (size_t k = 0; k < tm.triangleCount; ++k) {
      chartArea[charts.chartOfTriangle[k]] += areaM2(k);
      ++chartTriangles[charts.chartOfTriangle[k]];
    }
    const double texelsPerM2 = double(texelsPerMetre) * double(texelsPerMetre);
    for (size_t k = 0; k < tm.triangleCount; ++k) {
      const uint32_t c = charts.chartOfTriangle[k];
      keep[k] = chartArea[c] * texelsPerM2 >= kMinTexelsPerTriangle * double(chartTriangles[c]) ? 1 : 0;
    }
  }
  std::vector<uint32_t> kept;
  for (size_t k = 0; k < tm.triangleCount; ++k) {
    if (keep[k]) kept.insert(kept.end(), local.begin() + std::ptrdiff_t(3 * k), local.begin() + std::ptrdiff_t(3 * k + 3));
  }
  lt.cornerUv.assign(3 * size_t(tm.triangleCount), noLightTextureUv());
  if (kept.empty()) {
    lt.width = lt.height = 0;
    return;
  }
  const LightmapUv uv = generateLightmapUv(positions, kept, settings);
  lt.width = uv.width;
  lt.height = uv.height;
  lt.texelsPerMetre = uv.texelsPerMetre;
  lt.densityReduced = uv.densityReduced;
  size_t next = 0;
  for (size_t k = 0; k < tm.triangleCount; ++k) {
    if (!keep[k]) continue;
    for (size_t c = 0; c < 3; ++c) lt.cornerUv[3 * k + c] = uv.uv[uv.indices[next++]];
  }
}

// The share of the texels that the corner UVs' triangles cover (texel centres inside them) which more than one
// triangle covers: TEXCOORD_1 that overlaps itself would bake two places of the surface into one texel.
// TEXCOORD_1 with more of its texels under two triangles than this is not used as light-map UVs: 0.5 %,
// above the centres that rounding puts on both sides of a shared edge.
constexpr double kMaxUvOverlapShare = 0.005;

static double uvOverlapShare(const std::vector<vec2>& cornerUv, uint32_t width, uint32_t height) {
  std::vector<uint8_t> count(size_t(width) * height, 0);
  const dvec2 size(width, height);
  for (size_t c = 0; c + 2 < cornerUv.size(); c += 3) {
    const dvec2 a = dvec2(cornerUv[c]) * size, b = dvec2(cornerUv[c + 1]) * size, d = dvec2(cornerUv[c + 2]) * size;
    const double area = (b.x - a.x) * (d.y - a.y) - (b.y - a.y) * (d.x - a.x);
    if (!(std::abs(area) > 0.0)) continue;
    const int i0 = std::max(0, int(std::floor(std::min({a.x, b.x, d.x}))));
    const int i1 = std::min(int(width) - 1, int(std::floor(std::max({a.x, b.x, d.x}))));
    const int j0 = std::max(0, int(std::floor(std::min({a.y, b.y, d.y}))));
    const int j1 = std::min(int(height) - 1, int(std::floor(std::max({a.y, b.y, d.y}))));
    for (int j = j0; j <= j1; ++j) {
      for (int i = i0; i <= i1; ++i) {
        const dvec2 p(i + 0.5, j + 0.5);
        const double w0 = ((b.x - p.x) * (d.y - p.y) - (b.y - p.y) * (d.x - p.x)) / area;
        const double w1 = ((d.x - p.x) * (a.y - p.y) - (d.y - p.y) * (a.x - p.x)) / area;
        const double w2 = 1.0 - w0 - w1;
        // Strictly inside: a centre on an edge that two neighbours share counts for neither.
        if (w0 > 0.0 && w1 > 0.0 && w2 > 0.0) {
          uint8_t& n = count[size_t(j) * width + size_t(i)];
          n = uint8_t(std::min(255, n + 1));
        }
      }
    }
  }
  size_t covered = 0, overlapped = 0;
  for (uint8_t n : count) {
    covered += n > 0 ? 1 : 0;
    overlapped += n > 1 ? 1 : 0;
  }
  return covered > 0 ? double(overlapped) / double(covered) : 0.0;
}

TraceMaterial lowerMaterial(const sdb::Material& m, uint32_t sdbMaterialId) {
  TraceMaterial t;
  t.diffuse = m.effective().diffuse;
  t.reflection = m.reflectionColor;
  t.transmission = m.transmissionColor;
  t.fresnel = m.reflectionModel == sdb::ReflectionModel::kFresnel;
  t.ior = m.ior;
  t.reflectionGlossiness = m.reflectionGlossiness;
  t.anisotropyU = m.anisotropyU;
  t.anisotropyV = m.anisotropyV;
  t.anisotropyRotationRad = m.anisotropyRotationRad;
  t.transmissionGlossiness = m.transmissionGlossiness;
  t.emissionCdM2 = m.emissionDisplay ? Rgb(0.0f) : m.emissionLuminance;  // a display colour lights nothing
  t.doubleSided = m.doubleSided;
  t.sdbMaterialId = sdbMaterialId;
  t.reflectionFogDistanceM = m.reflectionFogDistanceM;
  t.reflectionFogColor = glm::clamp(m.reflectionFogColor, 0.0f, 1.0f);
  t.diffuseColor = glm::clamp(m.diffuseColor, 0.0f, 1.0f);
  t.normalScale = m.bumpScale;
  switch (m.alphaMode) {
    case sdb::AlphaMode::kOpaque:
      t.alpha = TraceAlpha::kOpaque;
      break;
    case sdb::AlphaMode::kMask:
      t.alpha = TraceAlpha::kMask;
      break;
    case sdb::AlphaMode::kBlend:
      t.alpha = TraceAlpha::kBlend;
      break;
  }
  t.opacity = std::clamp(m.opacity, 0.0f, 1.0f);
  t.alphaCutoff = m.alphaCutoff;
  t.carPaint = m.carPaint;
  return t;
}

TraceBrdfTable lowerBrdfTable(const std::string& file, std::shared_ptr<const BrdfTable> table) {
  TraceBrdfTable t;
  t.file = file;
  const BrdfTable::AlbedoPeak peak = table->maxAlbedo();
  t.table = std::move(table);
  t.maxAlbedo = peak.albedo;
  if (peak.albedo > 1.0f) {
    t.scale = 1.0f / peak.albedo;
    constexpr const char* kChannels[3] = {"red", "green", "blue"};
    char text[160];
    std::snprintf(text, sizeof text, "reflects %.3g of the %s light arriving at %.0f° from the normal (more than it receives); the baker scales it by %.3g",
                  double(peak.albedo), kChannels[peak.channel], double(peak.thetaInDeg), double(t.scale));
    log::warn("measured BRDF " + file + ": " + text);
  }
  return t;
}

TraceTextureSlot lowerTextureRef(const sdb::TextureRef& ref, uint32_t textureIndex) {
  TraceTextureSlot slot;
  slot.texture = textureIndex;
  slot.texCoord = ref.texCoord == 1 ? 1 : 0;
  auto wrap = [](sdb::WrapMode w) {
    switch (w) {
      case sdb::WrapMode::kClampToEdge:
        return TraceWrap::kClampToEdge;
      case sdb::WrapMode::kMirroredRepeat:
        return TraceWrap::kMirroredRepeat;
      case sdb::WrapMode::kRepeat:
        break;
    }
    return TraceWrap::kRepeat;
  };
  slot.wrapS = wrap(ref.wrapS);
  slot.wrapT = wrap(ref.wrapT);
  slot.nearest = ref.magFilter == sdb::MagFilter::kNearest;
  // KHR_texture_transform: uv' = T · R · S · uv with R's columns (cos θ, −sin θ) and (sin θ, cos θ), which
  // maps the extension's example (offset (0, 1), rotation π/2, scale 0.5) onto the image's lower-left
  // quadrant.
  const sdb::UvTransform& x = ref.transform;
  const float c = std::cos(x.rotationRad);
  const float s = std::sin(x.rotationRad);
  slot.uvFromU = vec2(c, -s) * x.scale.x;
  slot.uvFromV = vec2(s, c) * x.scale.y;
  slot.uvOffset = x.offset;
  return slot;
}

TraceTexture lowerTexture(const sdb::Texture& t) {
  if (t.width <= 0 || t.height <= 0 || t.channels < 1 || t.channels > 4 ||
      (t.bitsPerChannel != 8 && t.bitsPerChannel != 16) ||
      t.pixels.size() !=
          size_t(t.width) * size_t(t.height) * size_t(t.channels) * size_t(t.bitsPerChannel / 8)) {
    throw std::invalid_argument("texture \"" + t.name + "\" has inconsistent size, channels or pixel data");
  }
  TraceTexture out;
  out.width = uint32_t(t.width);
  out.height = uint32_t(t.height);
  out.channels = uint32_t(t.channels);
  const size_t values = size_t(t.width) * size_t(t.height) * size_t(t.channels);
  if (t.bitsPerChannel == 8) {
    out.texels = t.pixels;
  } else {
    out.texels.resize(values);
    for (size_t i = 0; i < values; ++i) {
      uint16_t v;
      std::memcpy(&v, t.pixels.data() + 2 * i, 2);
      out.texels[i] = uint8_t((uint32_t(v) * 255u + 32767u) / 65535u);
    }
  }
  return out;
}

std::vector<vec4> generateTangents(std::span<const vec3> positions, std::span<const vec3> normals,
                                   std::span<const vec2> uv, std::span<const uint32_t> indices) {
  const size_t n = positions.size();
  // Sums of ∂p/∂u and of ∂p/∂(−v): glTF's bitangent is a normal map's +Y, "up" in the image (glTF 2.0
  // material.schema.json, normalTexture), and texture coordinates start at the image's upper left corner (glTF
  // 2.0 specification, "Images"), so up is −v.
  std::vector<dvec3> tangentSum(n, dvec3(0.0)), bitangentSum(n, dvec3(0.0));
  if (uv.size() == n) {
    for (size_t k = 0; k + 2 < indices.size(); k += 3) {
      const uint32_t i0 = indices[k], i1 = indices[k + 1], i2 = indices[k + 2];
      const dvec3 e1 = dvec3(positions[i1]) - dvec3(positions[i0]);
      const dvec3 e2 = dvec3(positions[i2]) - dvec3(positions[i0]);
      const dvec2 d1 = dvec2(uv[i1]) - dvec2(uv[i0]);
      const dvec2 d2 = dvec2(uv[i2]) - dvec2(uv[i0]);
      // ∂p/∂u and −∂p/∂v of the triangle (Lengyel, "Mathematics for 3D Game Programming and Computer
      // Graphics", 3rd ed., §7.8.3: e = Δu · ∂p/∂u + Δv · ∂p/∂v), weighted by the triangle's area.
      const double det = d1.x * d2.y - d2.x * d1.y;
      if (!(std::abs(det) > 0.0) || !std::isfinite(det)) continue;
      const double area = 0.5 * glm::length(glm::cross(e1, e2));
      const dvec3 t = (e1 * d2.y - e2 * d1.y) / det;
      const dvec3 b = (e1 * d2.x - e2 * d1.x) / det;  // −∂p/∂v
      const double tl = glm::length(t), bl = glm::length(b);
      if (!(tl > 0.0) || !(bl > 0.0) || !std::isfinite(tl) || !std::isfinite(bl)) continue;
      for (uint32_t i : {i0, i1, i2}) {
        tangentSum[i] += area * t / tl;
        bitangentSum[i] += area * b / bl;
      }
    }
  }
  std::vector<vec4> out(n);
  for (size_t i = 0; i < n; ++i) {
    const dvec3 nn(normals[i]);
    // Gram–Schmidt against the normal; any perpendicular where the UVs give no direction.
    dvec3 t = tangentSum[i] - glm::dot(tangentSum[i], nn) * nn;
    std::optional<vec3> unit = unitOrNone(t);
    if (!unit) {
      const dvec3 helper = std::abs(nn.x) < 0.9 ? dvec3(1, 0, 0) : dvec3(0, 1, 0);
      unit = unitOrNone(glm::cross(helper, nn));
    }
    const vec3 tangent = unit.value_or(vec3(1, 0, 0));
    const float w = glm::dot(glm::cross(nn, dvec3(tangent)), bitangentSum[i]) < 0.0 ? -1.0f : 1.0f;
    out[i] = vec4(tangent, w);
  }
  return out;
}

TraceGoniometricTable tabulateGoniometric(const sdb::IesProfile& profile, uint32_t gammaSteps, uint32_t cSteps) {
  if (gammaSteps < 2 || cSteps < 1) {
    throw std::invalid_argument("tabulateGoniometric: need at least 2 gamma steps and 1 C step");
  }
  TraceGoniometricTable t;
  t.gammaSteps = gammaSteps;
  t.cSteps = cSteps;
  t.candelaCd.resize(size_t(gammaSteps) * cSteps);
  for (uint32_t c = 0; c < cSteps; ++c) {
    const double cRad = 2.0 * kPi * c / cSteps;
    for (uint32_t g = 0; g < gammaSteps; ++g) {
      const double gammaRad = kPi * g / (gammaSteps - 1);
      const double s = std::sin(gammaRad);
      t.candelaCd[size_t(c) * gammaSteps + g] =
          float(profile.candelaTowards(s * std::cos(cRad), s * std::sin(cRad), std::cos(gammaRad)));
    }
  }
  return t;
}

TraceSky tabulateSky(const sunsky::Sky& sky, const sunsky::SiteFrame& frame, uint32_t resolution,
                     uint32_t cellSamples) {
  if (resolution < 1 || resolution > 1024 || cellSamples < 1 || cellSamples > 64) {
    throw std::invalid_argument("tabulateSky: resolution must be in [1, 1024] and cell samples in [1, 64]");
  }
  TraceSky t;
  t.resolution = resolution;
  t.radianceCdM2.resize(size_t(resolution) * resolution);
  const double n = cellSamples;
  for (uint32_t j = 0; j < resolution; ++j) {
    for (uint32_t i = 0; i < resolution; ++i) {
      dvec3 sum(0.0);
      for (uint32_t b = 0; b < cellSamples; ++b) {
        const double mu = 1.0 - (j + (b + 0.5) / n) / resolution;
        const double sinTheta = std::sqrt(std::max(0.0, 1.0 - mu * mu));
        for (uint32_t a = 0; a < cellSamples; ++a) {
          const double phi = 2.0 * kPi * (i + (a + 0.5) / n) / resolution;
          const dvec3 world(sinTheta * std::cos(phi), mu, sinTheta * std::sin(phi));  // φ = atan2(z, x)
          sum += dvec3(sky.radianceCdM2(frame.enuFromWorld(world)));
        }
      }
      t.radianceCdM2[size_t(j) * resolution + i] = Rgb(sum / (n * n));
    }
  }
  return t;
}

namespace {

// Whether a material reads the per-vertex tangents: for its normal map or its anisotropy's axes.
bool readsTangents(const TraceMaterial& m) {
  return bool(m.normalTexture) || m.isAnisotropic();
}

class Builder {
 public:
  Builder(const sdb::Scene& scene, const TraceBuildOptions& options) : scene_(scene), options_(options) {
    rdb_.materials.push_back(lowerMaterial(scene.material(sdb::MaterialId{}), 0));
    materialIndex_[0] = 0;
  }

  TraceRdb build() {
    // First the materials (in the order the meshes meet them, as addMesh would), which per-vertex attributes
    // they read and the sizes, so that addMesh appends only those attributes into arrays reserved once.
    size_t vertices = 0;
    size_t triangles = 0;
    scene_.forEachNode([&](sdb::NodeId id, const mat4&) {
      for (sdb::MeshId meshId : scene_.node(id).meshes) {
        const sdb::Mesh& mesh = scene_.mesh(meshId);
        needTangents_ = needTangents_ || readsTangents(rdb_.materials[materialIndex(mesh.material)]);
        anyColors_ = anyColors_ || !mesh.colors.empty();
        vertices += mesh.vertexCount();
        triangles += mesh.triangleCount();
      }
    });
    rdb_.positionsM.reserve(vertices);
    rdb_.normals.reserve(vertices);
    if (needUv_[0]) rdb_.uv0.reserve(vertices);
    if (needUv_[1]) rdb_.uv1.reserve(vertices);
    if (anyColors_) rdb_.colors.reserve(vertices);
    if (needTangents_) rdb_.tangents.reserve(vertices);
    rdb_.indices.reserve(3 * triangles);
    rdb_.triangleMaterial.reserve(triangles);
    scene_.forEachNode([&](sdb::NodeId id, const mat4& worldFromLocal) {
      const sdb::Node& node = scene_.node(id);
      for (sdb::MeshId mesh : node.meshes) addMesh(id, mesh, worldFromLocal);
      if (node.light) addLight(node, worldFromLocal);
    });
    addDaylight();
    for (const sdb::Portal& portal : scene_.portals()) {
      const std::vector<vec3> cornersM = sdb::portalTrianglesM(portal);
      rdb_.portalCornersM.insert(rdb_.portalCornersM.end(), cornersM.begin(), cornersM.end());
    }
    return std::move(rdb_);
  }

 private:
  uint32_t materialIndex(sdb::MaterialId id) {
    const auto [it, added] = materialIndex_.try_emplace(id.value, uint32_t(rdb_.materials.size()));
    if (added) rdb_.materials.push_back(lowerWithTextures(scene_.material(id), id.value));
    return it->second;
  }

  TraceMaterial lowerWithTextures(const sdb::Material& m, uint32_t sdbMaterialId) {
    TraceMaterial t = lowerMaterial(m, sdbMaterialId);
    auto slot = [&](const sdb::TextureRef& ref) {
      if (!ref) return TraceTextureSlot{};
      const auto [it, added] = textureIndex_.try_emplace(ref.texture.value, uint32_t(rdb_.textures.size()));
      if (added) rdb_.textures.push_back(lowerTexture(scene_.texture(ref.texture)));
      needUv_[ref.texCoord == 1 ? 1 : 0] = true;
      return lowerTextureRef(ref, it->second);
    };
    t.diffuseTexture = slot(m.diffuseTexture);
    t.reflectionTexture = slot(m.reflectionTexture);
    t.reflectionTextureSrgb = m.reflectionTextureSrgb;
    t.glossinessTexture = slot(m.reflectionGlossinessTexture);
    t.transmissionTexture = slot(m.transmissionTexture);
    t.emissionTexture = slot(m.emissionTexture);
    t.normalTexture = slot(m.bumpTexture);
    if (m.isAnisotropic()) {
      t.anisotropyTexture = slot(m.anisotropyTexture);
      t.anisotropyRotationTexture = slot(m.anisotropyRotationTexture);
    }
    t.metalnessTexture = slot(m.metalnessTexture);
    if (t.metalnessTexture) t.metalness = std::clamp(m.metalnessFactor, 0.0f, 1.0f);
    if (m.measuredBrdf) {
      // One table per file (materials that name it read it each), or per table where the SDB has no file.
      const std::string key = m.measuredBrdfPath.empty()
                                  ? "table@" + std::to_string(reinterpret_cast<uintptr_t>(m.measuredBrdf.get()))
                                  : "file:" + m.measuredBrdfPath;
      const auto [it, added] = brdfTableIndex_.try_emplace(key, uint32_t(rdb_.brdfTables.size()));
      if (added) rdb_.brdfTables.push_back(lowerBrdfTable(m.measuredBrdfPath, m.measuredBrdf));
      t.brdfTable = it->second;
    }
    return t;
  }

  void addMesh(sdb::NodeId nodeId, sdb::MeshId meshId, const mat4& worldFromLocal) {
    const sdb::Mesh& mesh = scene_.mesh(meshId);
    const uint32_t material = materialIndex(mesh.material);
    const bool emissive = scene_.material(mesh.material).isEmissive();
    TraceMesh tm;
    tm.sdbMeshId = meshId.value;
    tm.sdbNodeId = nodeId.value;
    tm.firstVertex = uint32_t(rdb_.positionsM.size());
    tm.vertexCount = uint32_t(mesh.vertexCount());
    tm.firstTriangle = uint32_t(rdb_.triangleCount());
    tm.twoSided = mesh.twoSided;

    const PlacedMesh placed = placeMesh(mesh, worldFromLocal, rdb_.positionsM, rdb_.normals);
    const std::span<const vec3> positionsM(rdb_.positionsM.data() + tm.firstVertex, mesh.vertexCount());
    const std::span<const vec3> normals(rdb_.normals.data() + tm.firstVertex, mesh.vertexCount());
    for (const vec3& p : positionsM) rdb_.boundsM.extend(p);
    rdb_.skippedTriangles += placed.skippedTriangles;
    // The per-vertex attributes that some material reads (build() found which), for every vertex.
    auto append = [](bool needed, auto& to, const auto& from, size_t count, const auto& fallback) {
      if (!needed) return;
      if (from.size() == count) {
        to.insert(to.end(), from.begin(), from.end());
      } else {
        to.insert(to.end(), count, fallback);
      }
    };
    append(needUv_[0], rdb_.uv0, mesh.uv0, mesh.vertexCount(), vec2(0.0f));
    append(needUv_[1], rdb_.uv1, mesh.uv1, mesh.vertexCount(), vec2(0.0f));
    append(anyColors_, rdb_.colors, mesh.colors, mesh.vertexCount(), vec4(1.0f));
    const TraceMaterial& tmat = rdb_.materials[material];
    if (readsTangents(tmat)) {
      std::vector<vec4> tangents;
      if (mesh.tangents.size() == mesh.vertexCount()) {
        // Tangents are directions: the linear part of worldFromLocal, and a mirroring transform flips the
        // bitangent's sign.
        const glm::dmat3 linear(worldFromLocal);
        const double sign = glm::determinant(linear) < 0.0 ? -1.0 : 1.0;
        for (size_t i = 0; i < mesh.vertexCount(); ++i) {
          const dvec3 n(normals[i]);
          dvec3 t = linear * dvec3(vec3(mesh.tangents[i]));
          t -= glm::dot(t, n) * n;
          const std::optional<vec3> unit = unitOrNone(t);
          tangents.push_back(unit ? vec4(*unit, float(sign) * (mesh.tangents[i].w < 0.0f ? -1.0f : 1.0f))
                                  : vec4(0.0f));
        }
      }
      // The UV set whose directions the tangents follow: the normal map's, else the anisotropy textures'.
      const TraceTextureSlot& uvSlot = tmat.normalTexture       ? tmat.normalTexture
                                       : tmat.anisotropyTexture ? tmat.anisotropyTexture
                                                                : tmat.anisotropyRotationTexture;
      const std::vector<vec2>& uv = uvSlot.texCoord == 1 ? mesh.uv1 : mesh.uv0;
      if (tangents.empty() && uv.size() != mesh.vertexCount() && tmat.isAnisotropic()) {
        log::warn(
            "mesh \"" + mesh.name + "\": its material \"" + scene_.material(mesh.material).name +
            "\" reflects anisotropically along the surface's tangent, but the mesh has neither tangents "
            "nor TEXCOORD_" +
            std::to_string(uvSlot.texCoord == 1 ? 1 : 0) +
            " to give its direction; the baker uses an arbitrary tangent (add UVs or tangents)");
      }
      const std::vector<vec4> generated = generateTangents(positionsM, normals, uv, placed.indices);
      if (tangents.empty()) {
        tangents = generated;
      } else {
        for (size_t i = 0; i < tangents.size(); ++i) {
          if (tangents[i] == vec4(0.0f)) tangents[i] = generated[i];  // a degenerate tangent in the file
        }
      }
      rdb_.tangents.insert(rdb_.tangents.end(), tangents.begin(), tangents.end());
    } else if (needTangents_) {
      rdb_.tangents.insert(rdb_.tangents.end(), mesh.vertexCount(), vec4(1.0f, 0.0f, 0.0f, 1.0f));
    }
    for (size_t k = 0; k < placed.sdbTriangle.size(); ++k) {
      if (emissive) rdb_.emissiveTriangles.push_back(uint32_t(rdb_.triangleCount()));
      for (size_t c = 0; c < 3; ++c) rdb_.indices.push_back(tm.firstVertex + placed.indices[3 * k + c]);
      rdb_.triangleMaterial.push_back(material);
    }
    tm.triangleCount = uint32_t(rdb_.triangleCount()) - tm.firstTriangle;
    addLightTexture(mesh, tm);
    rdb_.meshes.push_back(tm);
  }

  void addLightTexture(const sdb::Mesh& mesh, TraceMesh& tm) {
    tm.automaticLightTextureAllowed = !mesh.lightTexture.enabled && mesh.lightTexture.allowAutomatic;
    if (!mesh.lightTexture.enabled) return;
    if (tm.triangleCount == 0 || tm.vertexCount == 0) {
      log::warn("mesh \"" + mesh.name + "\" asks for a light texture but has no triangles of non-zero area; it gets "
                "none");
      return;
    }
    const float density = mesh.lightTexture.texelsPerMetre > 0.0f ? mesh.lightTexture.texelsPerMetre
                                                                  : float(scene_.bakeSettings().texelsPerMetre);
    const int maxSize = options_.lightTextureMaxSize;
    TraceLightTexture lt;
    lt.mesh = uint32_t(rdb_.meshes.size());
    const uint32_t* corners = rdb_.indices.data() + 3 * size_t(tm.firstTriangle);
    const size_t cornerCount = 3 * size_t(tm.triangleCount);
    if (!mesh.uv1.empty()) {
      // The UV area the triangles cover; TEXCOORD_1 outside [0, 1]² would wrap onto other charts.
      double uvArea = 0.0;
      double areaM2 = 0.0;
      bool inside = true;
      for (size_t c = 0; c < cornerCount; c += 3) {
        const dvec2 a(mesh.uv1[corners[c] - tm.firstVertex]);
        const dvec2 b(mesh.uv1[corners[c + 1] - tm.firstVertex]);
        const dvec2 d(mesh.uv1[corners[c + 2] - tm.firstVertex]);
        uvArea += 0.5 * std::abs((b.x - a.x) * (d.y - a.y) - (b.y - a.y) * (d.x - a.x));
        const dvec3 p0(rdb_.positionsM[corners[c]]);
        areaM2 += 0.5 * glm::length(glm::cross(dvec3(rdb_.positionsM[corners[c + 1]]) - p0,
                                               dvec3(rdb_.positionsM[corners[c + 2]]) - p0));
        for (const dvec2& uv : {a, b, d}) {
          inside = inside && uv.x >= 0.0 && uv.x <= 1.0 && uv.y >= 0.0 && uv.y <= 1.0;
        }
      }
      if (inside && uvArea > 0.0 && std::isfinite(uvArea) && areaM2 > 0.0) {
        // A square atlas whose mean density over the mesh is the requested one.
        const double side = std::ceil(double(density) * std::sqrt(areaM2 / uvArea));
        lt.width = lt.height = uint32_t(std::clamp(side, 1.0, double(maxSize)));
        lt.texelsPerMetre = float(double(lt.width) * std::sqrt(uvArea / areaM2));
        lt.fromTexcoord1 = true;
        for (size_t c = 0; c < cornerCount; ++c) lt.cornerUv.push_back(mesh.uv1[corners[c] - tm.firstVertex]);
        // Overlapping UVs (mirrored or stacked charts, a texture-painting layout) would share texels between
        // places of the surface.
        const double overlap = uvOverlapShare(lt.cornerUv, lt.width, lt.height);
        if (overlap > kMaxUvOverlapShare) {
          char share[32];
          std::snprintf(share, sizeof share, "%.1f %%", 100.0 * overlap);
          log::warn("mesh \"" + mesh.name + "\": TEXCOORD_1 overlaps itself (" + share +
                    " of its texels lie under more than one triangle), so it cannot hold a light texture; "
                    "generating light-map UVs instead");
          lt = TraceLightTexture{};
          lt.mesh = uint32_t(rdb_.meshes.size());
        }
      } else {
        log::warn("mesh \"" + mesh.name + "\": TEXCOORD_1 is not usable as light-map UVs (" +
                  (inside ? "the triangles cover no area" : "coordinates outside [0, 1]") +
                  "); generating light-map UVs instead");
      }
    }
    if (!lt.fromTexcoord1) {
      generateAtlas(rdb_, tm, density, maxSize, options_.lightTexturePaddingTexels, true, lt);
      if (lt.densityReduced) {
        log::warn("mesh \"" + mesh.name + "\": light texture density reduced from " +
                  std::to_string(density) + " to " + std::to_string(lt.texelsPerMetre) + " texels/m to fit " +
                  std::to_string(maxSize) + "² texels");
      }
    }
    tm.lightTexture = uint32_t(rdb_.lightTextures.size());
    rdb_.lightTextures.push_back(std::move(lt));
  }

  void addLight(const sdb::Node& node, const mat4& worldFromLocal) {
    const sdb::Light& light = scene_.light(node.light);
    TracePunctualLight t;
    t.sdbLightId = node.light.value;
    const LightFrame frame = placeLight(scene_, node, worldFromLocal);
    t.positionM = frame.positionM;
    t.directionWorld = frame.directionWorld;
    t.cAxisWorld = frame.cAxisWorld;
    t.intensity = light.color * light.intensity;
    t.rangeM = light.rangeM;
    switch (light.type) {
      case sdb::LightType::kPoint: t.type = PunctualType::kPoint; break;
      case sdb::LightType::kDirectional: t.type = PunctualType::kDirectional; break;
      case sdb::LightType::kSpot:
        t.type = PunctualType::kSpot;
        t.cosInner = std::cos(light.innerConeRad);
        t.cosOuter = std::cos(light.outerConeRad);
        break;
      case sdb::LightType::kGoniometric:
        t.type = PunctualType::kGoniometric;
        t.goniometricTable = uint32_t(rdb_.goniometricTables.size());
        rdb_.goniometricTables.push_back(
            tabulateGoniometric(*light.ies, options_.goniometricGammaSteps, options_.goniometricCSteps));
        break;
    }
    rdb_.punctualLights.push_back(t);
  }

  void addDaylight() {
    const std::optional<SceneDaylight> daylight = lowerDaylight(scene_);
    if (!daylight) return;
    if (daylight->sun) {
      rdb_.hasSun = true;
      rdb_.sun.directionWorld = vec3(daylight->sunDirWorld);
      rdb_.sun.normalIlluminanceLux = daylight->sun->normalIlluminanceLux;
      rdb_.sun.halfAngleRad = float(degToRad(sunsky::kSunAngularDiameterDeg / 2.0));
    }
    if (daylight->sky) {
      rdb_.sky = tabulateSky(*daylight->sky, daylight->frame, options_.skyResolution, options_.skyCellSamples);
    }
  }

  const sdb::Scene& scene_;
  const TraceBuildOptions& options_;
  TraceRdb rdb_;
  std::map<uint32_t, uint32_t> materialIndex_;  // SDB material id → index into rdb_.materials
  std::map<uint32_t, uint32_t> textureIndex_;   // SDB texture id → index into rdb_.textures
  std::map<std::string, uint32_t> brdfTableIndex_;  // measured BRDF file (or table) → index into rdb_.brdfTables
  bool needUv_[2] = {false, false};             // some texture slot reads TEXCOORD_0 / TEXCOORD_1
  bool anyColors_ = false;                      // some placed mesh has COLOR_0
  bool needTangents_ = false;                   // some placed mesh's material reads tangents (readsTangents)
};

}  // namespace

TraceRdb buildTraceRdb(const sdb::Scene& scene, const TraceBuildOptions& options) {
  if (options.skyResolution < 1 || options.skyResolution > 1024 || options.skyCellSamples < 1 ||
      options.skyCellSamples > 64 || options.goniometricGammaSteps < 2 || options.goniometricCSteps < 1 ||
      options.lightTextureMaxSize < 8 ||
      options.lightTextureMaxSize > 16384 || options.lightTexturePaddingTexels < 0 ||
      options.lightTexturePaddingTexels > 16) {
    throw std::invalid_argument("buildTraceRdb: an option is out of range (see TraceBuildOptions)");
  }
  return Builder(scene, options).build();
}

TraceLightTexture* addAutomaticLightTexture(TraceRdb& rdb, uint32_t mesh, float texelsPerMetre, int maxSize,
                                            int paddingTexels) {
  if (mesh >= rdb.meshes.size() || rdb.meshes[mesh].lightTexture != TraceMesh::kNoLightTexture ||
      rdb.meshes[mesh].triangleCount == 0 || !(texelsPerMetre > 0.0f) || maxSize < 8 || paddingTexels < 0) {
    throw std::invalid_argument("addAutomaticLightTexture: no such mesh, it has a light texture, or bad settings");
  }
  TraceLightTexture lt;
  lt.mesh = mesh;
  lt.automatic = true;
  generateAtlas(rdb, rdb.meshes[mesh], texelsPerMetre, maxSize, paddingTexels, false, lt);
  if (lt.width == 0) return nullptr;
  // Keep lightTextures in mesh order.
  auto at = std::find_if(rdb.lightTextures.begin(), rdb.lightTextures.end(),
                         [&](const TraceLightTexture& t) { return t.mesh > mesh; });
  at = rdb.lightTextures.insert(at, std::move(lt));
  for (uint32_t k = 0; k < rdb.lightTextures.size(); ++k) rdb.meshes[rdb.lightTextures[k].mesh].lightTexture = k;
  return &*at;
}

}  // namespace fly::rdb
