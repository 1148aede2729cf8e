#include "raytracer/integrator.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "base/log.h"
#include "base/spot_cone.h"
#include "raytracer/warp.h"

namespace fly::raytracer {
namespace {

// Veach & Guibas 1995, the power heuristic with β = 2, one sample from each technique: the weight of the
// technique that drew the sample, with density a, against the other's b.
float powerHeuristic(float a, float b) {
  if (std::isinf(a)) return 1.0f;
  const float a2 = a * a;
  const float b2 = b * b;
  return a2 + b2 > 0.0f ? a2 / (a2 + b2) : 0.0f;
}

// Sampler dimension groups per path vertex: (sun, sky), (continuation, emitter), (Russian roulette, BSDF lobe
// choice, punctual light choice). The continuation takes the group's first pair, a (0, m, 2)-net.
constexpr uint32_t kGroupsPerVertex = 3;

// The first path vertex at which Russian roulette may end a path (the sensor is vertex 0). From vertex 2 on
// it ended most paths at the second surface they reached (q ≈ ρ₁ρ₂, weights ≈ 1 / ρ₁ρ₂), and in daylight
// scenes, where sunlit ground lights the walls, that second bounce carries much light: on
// bench/bench_baker.cpp's sun-and-sky scene at 64 samples, starting at vertex 3 cut the RMSE by 8 % (MC) and
// 17 % (QMC) for 2.4 % more rays per sample (docs/benchmarks.md).
constexpr uint32_t kFirstRouletteVertex = 3;

// The least cosine between a hit's shading normal and the direction back along the ray (sampleIrradiance).
constexpr float kMinShadingCos = 0.01f;

// The first of the sampler groups of next-event estimation to lit patches: path vertex k uses groups
// kPatchGroupBase + 2k (the triangle and the point on it) and + 2k + 1 (the patch's sun, and sky),
// far above the path's own groups (kGroupsPerVertex per vertex, at most kPathLengthGuard vertices) and below
// the baker's (raytracer/baker.cpp). ≡ 29 mod 32: the sensor's two groups share SobolSampler's group cache
// only with a path's tenth and eleventh vertices.
constexpr uint32_t kPatchGroupBase = (1u << 19) + 29;

// The sampler group of reflection fog's choice at path vertex k: kFogGroupBase + k, above the lit patches'
// groups (kPatchGroupBase + 2k + 1 ≤ 2¹⁹ + 20031) and below the baker's (2²⁰ + 31).
constexpr uint32_t kFogGroupBase = (1u << 19) + (1u << 18) + 27;

// Reflection fog's share t(d) = min(d / D, 1) at reflected distance distM (∞ for a ray that meets nothing)
// for fog distance fogDistanceM D (finite): linear, reaching the fog colour at D (HOOPS Luminate's realistic material,
// "Reflection Fog": "at a certain distance, the color of the reflection becomes equal to the specified reflection fog
// color").
float fogFraction(float distM, float fogDistanceM) {
  return std::min(distM / fogDistanceM, 1.0f);
}

// Points per face of LitPatches' mean radiance of a face (Integrator::faceRadiance).
constexpr uint32_t kFaceRadianceSamples = 8;


// Direction of the sky table's (u, v) = (φ / 2π, 1 − μ), φ = atan2(d.z, d.x) (TraceSky).
vec3 skyDirection(const vec2& uv) {
  const float mu = 1.0f - uv.y;
  const float sinTheta = std::sqrt(std::max(0.0f, 1.0f - mu * mu));
  const vec2 sc = sinCosTwoPi(uv.x);
  return vec3(sinTheta * sc.y, mu, sinTheta * sc.x);
}

vec2 skyUv(const vec3& d) {
  float phi = atan2Approx(d.z, d.x);
  if (phi < 0.0f) phi += 2.0f * kPiF;
  return vec2(std::min(phi / (2.0f * kPiF), 0x1.fffffep-1f), std::clamp(1.0f - d.y, 0.0f, 0x1.fffffep-1f));
}

// A measured intensity table at (γ, C) in radians, bilinear, wrapping in C (TraceGoniometricTable).
float goniometricCandela(const rdb::TraceGoniometricTable& table, float gammaRad, float cRad) {
  const float g = std::clamp(gammaRad / kPiF, 0.0f, 1.0f) * static_cast<float>(table.gammaSteps - 1);
  float c = cRad / (2.0f * kPiF) * static_cast<float>(table.cSteps);
  c -= std::floor(c / static_cast<float>(table.cSteps)) * static_cast<float>(table.cSteps);
  const auto g0 = std::min(static_cast<uint32_t>(g), table.gammaSteps - 1);
  const uint32_t g1 = std::min(g0 + 1, table.gammaSteps - 1);
  const auto c0 = std::min(static_cast<uint32_t>(c), table.cSteps - 1);
  const uint32_t c1 = (c0 + 1) % table.cSteps;
  const float fg = g - static_cast<float>(g0);
  const float fc = c - static_cast<float>(c0);
  auto at = [&](uint32_t ci, uint32_t gi) { return table.candelaCd[ci * table.gammaSteps + gi]; };
  return (1.0f - fc) * ((1.0f - fg) * at(c0, g0) + fg * at(c0, g1)) +
         fc * ((1.0f - fg) * at(c1, g0) + fg * at(c1, g1));
}

// The mean emitted luminance of material m over its emission texture's texels (cd/m²), or of its constant.
float meanEmittedLuminance(const rdb::TraceRdb& rdb, const rdb::TraceMaterial& m) {
  if (!m.emissionTexture) return std::max(luminance(m.emissionCdM2), 0.0f);
  const rdb::TraceTexture& tex = rdb.textures.at(m.emissionTexture.texture);
  double sum = 0.0;
  rdb::TraceTextureSlot texel = m.emissionTexture;
  texel.uvFromU = vec2(1.0f, 0.0f);
  texel.uvFromV = vec2(0.0f, 1.0f);
  texel.uvOffset = vec2(0.0f);
  for (uint32_t y = 0; y < tex.height; ++y) {
    for (uint32_t x = 0; x < tex.width; ++x) {
      // At the texel's centre the bilinear lookup is the texel.
      const vec2 centre((float(x) + 0.5f) / float(tex.width), (float(y) + 0.5f) / float(tex.height));
      sum += std::max(luminance(m.emissionCdM2 * Rgb(sampleTexture(rdb, texel, centre, true))), 0.0f);
    }
  }
  return float(sum / (double(tex.width) * double(tex.height)));
}

}  // namespace

Integrator::Integrator(const rdb::TraceRdb& rdb, const EmbreeScene& scene, IntegratorSettings settings)
    : rdb_(rdb), scene_(scene), settings_(settings) {
  if (!(settings_.rouletteWindow > 0.0f && settings_.rouletteWindow <= 1.0f)) {
    throw std::invalid_argument("Integrator: rouletteWindow " + std::to_string(settings_.rouletteWindow) +
                                " is not in (0, 1]");
  }
  if (rdb.triangleMaterial.size() != rdb.triangleCount()) {
    throw std::invalid_argument("Integrator: " + std::to_string(rdb.triangleMaterial.size()) +
                                " triangle materials for " + std::to_string(rdb.triangleCount()) +
                                " triangles");
  }
  for (uint32_t m : rdb.triangleMaterial) {
    if (m >= rdb.materials.size()) {
      throw std::invalid_argument("Integrator: material index " + std::to_string(m) + " of " +
                                  std::to_string(rdb.materials.size()) + " materials");
    }
  }
  for (const rdb::TraceMaterial& m : rdb.materials) {
    if (m.brdfTable != rdb::TraceMaterial::kNoBrdfTable &&
        (m.brdfTable >= rdb.brdfTables.size() || !rdb.brdfTables[m.brdfTable].table)) {
      throw std::invalid_argument("Integrator: measured BRDF table " + std::to_string(m.brdfTable) +
                                  " does not exist");
    }
  }
  for (const rdb::TracePunctualLight& light : rdb.punctualLights) {
    if (light.type != rdb::PunctualType::kGoniometric) continue;
    if (light.goniometricTable >= rdb.goniometricTables.size()) {
      throw std::invalid_argument("Integrator: goniometric table " + std::to_string(light.goniometricTable) +
                                  " does not exist");
    }
    const rdb::TraceGoniometricTable& table = rdb.goniometricTables[light.goniometricTable];
    if (table.gammaSteps < 2 || table.cSteps < 1 ||
        table.candelaCd.size() != table.gammaSteps * table.cSteps) {
      throw std::invalid_argument("Integrator: goniometric table " + std::to_string(light.goniometricTable) +
                                  " needs gammaSteps >= 2, cSteps >= 1 and gammaSteps * cSteps values");
    }
  }

  const uint32_t res = rdb.sky.resolution;
  if (res > 0) {
    if (rdb.sky.radianceCdM2.size() != size_t{res} * res) {
      throw std::invalid_argument("Integrator: the sky table has " +
                                  std::to_string(rdb.sky.radianceCdM2.size()) + " cells for resolution " +
                                  std::to_string(res));
    }
    std::vector<float> luminances(rdb.sky.radianceCdM2.size());
    for (size_t i = 0; i < luminances.size(); ++i) {
      luminances[i] = std::max(luminance(rdb.sky.radianceCdM2[i]), 0.0f);
    }
    Distribution2D sky(luminances, res, res);
    if (!sky.allZero()) {
      // dω = dφ dμ = 2π du dv.
      skyPdfPerSr_.resize(luminances.size());
      for (uint32_t j = 0; j < res; ++j) {
        for (uint32_t i = 0; i < res; ++i) {
          const vec2 centre((static_cast<float>(i) + 0.5f) / static_cast<float>(res),
                            (static_cast<float>(j) + 0.5f) / static_cast<float>(res));
          skyPdfPerSr_[j * res + i] = sky.pdf(centre) / (2.0f * kPiF);
        }
      }
      skyDistribution_.emplace(std::move(sky));
    }
  }

  // Per-vertex attributes: one per vertex where materials read them (TraceRdb).
  bool readsUv[2] = {false, false};
  bool readsTangents = false;
  for (const rdb::TraceMaterial& m : rdb.materials) {
    for (const rdb::TraceTextureSlot* slot :
         {&m.diffuseTexture, &m.reflectionTexture, &m.glossinessTexture, &m.transmissionTexture,
          &m.emissionTexture, &m.normalTexture, &m.anisotropyTexture, &m.anisotropyRotationTexture,
          &m.metalnessTexture}) {
      if (!*slot) continue;
      if (slot->texture >= rdb.textures.size()) {
        throw std::invalid_argument("Integrator: texture " + std::to_string(slot->texture) + " of " +
                                    std::to_string(rdb.textures.size()) + " textures");
      }
      readsUv[slot->texCoord == 1 ? 1 : 0] = true;
    }
    readsTangents = readsTangents || bool(m.normalTexture) || m.isAnisotropic();
  }
  for (const rdb::TraceTexture& tex : rdb.textures) {
    if (tex.width < 1 || tex.height < 1 || tex.channels < 1 || tex.channels > 4 ||
        tex.texels.size() != size_t{tex.width} * tex.height * tex.channels) {
      throw std::invalid_argument("Integrator: a texture's size, channels and texels disagree");
    }
  }
  const size_t vertices = rdb.positionsM.size();
  if (rdb.normals.size() != vertices || (readsUv[0] && rdb.uv0.size() != vertices) ||
      (readsUv[1] && rdb.uv1.size() != vertices) || (!rdb.colors.empty() && rdb.colors.size() != vertices) ||
      (readsTangents && rdb.tangents.size() != vertices)) {
    throw std::invalid_argument(
        "Integrator: normals, texture coordinates, colours or tangents that materials "
        "read are given for some vertices only");
  }

  emitterPmfOfTriangle_.assign(rdb.triangleCount(), 0.0f);
  if (!rdb.emissiveTriangles.empty()) {
    std::vector<float> powers;
    powers.reserve(rdb.emissiveTriangles.size());
    // Triangles are chosen by area × the material's mean luminance: its emission, or with an emission
    // texture the mean over the texture's texels of the emission times the texel (any weight that is positive
    // wherever a triangle emits keeps the estimate unbiased; the texture is evaluated at the sampled point).
    std::vector<float> materialLuminance(rdb.materials.size(), -1.0f);
    for (uint32_t t : rdb.emissiveTriangles) {
      const uint32_t mi = rdb.triangleMaterial.at(t);
      const rdb::TraceMaterial& m = rdb.materials[mi];
      if (materialLuminance[mi] < 0.0f) materialLuminance[mi] = meanEmittedLuminance(rdb, m);
      const float sides = m.doubleSided ? 2.0f : 1.0f;
      powers.push_back(sides * scene.triangleAreaM2(t) * materialLuminance[mi]);
    }
    Distribution1D emitters(powers);
    if (!emitters.allZero()) {
      for (size_t i = 0; i < rdb.emissiveTriangles.size(); ++i) {
        emitterPmfOfTriangle_[rdb.emissiveTriangles[i]] += emitters.pmf(static_cast<uint32_t>(i));
      }
      emitterDistribution_.emplace(std::move(emitters));
    }
  }

  // GGX α of regularised lobes (kRegularizedGlossiness²), and the θh radius over which a measured table's
  // highlights are spread to match it (TabulatedLobe::regularised).
  constexpr float kMinAlpha = kRegularizedGlossiness * kRegularizedGlossiness;
  const float regularisedRadiusRad = std::atan(kMinAlpha);
  const size_t tables = rdb.brdfTables.size();
  for (const rdb::TraceBrdfTable& table : rdb.brdfTables) {
    measuredLobes_.push_back(std::make_unique<TabulatedLobe>(table.table, table.scale));
  }
  if (!settings_.caustics) {
    for (const rdb::TraceBrdfTable& table : rdb.brdfTables) {
      measuredLobes_.push_back(std::make_unique<TabulatedLobe>(
          TabulatedLobe::regularised(*table.table, regularisedRadiusRad), table.scale));
    }
  }
  for (const rdb::TraceMaterial& m : rdb.materials) {
    const MeasuredLobe* lobe = nullptr;
    const MeasuredLobe* deltaLightLobe = nullptr;
    if (m.brdfTable != rdb::TraceMaterial::kNoBrdfTable) {
      lobe = measuredLobes_[m.brdfTable].get();
      deltaLightLobe = settings_.caustics ? lobe : measuredLobes_[tables + m.brdfTable].get();
    } else if (m.carPaint) {
      measuredLobes_.push_back(std::make_unique<CarPaintBsdfLobe>(*m.carPaint));
      lobe = deltaLightLobe = measuredLobes_.back().get();
      if (!settings_.caustics) {
        // The coat's and flakes' highlights regularised as the analytic lobes are (kRegularizedGlossiness).
        CarPaintBrdf regularised = *m.carPaint;
        regularised.coatAlpha = std::max(regularised.coatAlpha, kMinAlpha);
        for (CarPaintLobe& flakes : regularised.lobes) flakes.alpha = std::max(flakes.alpha, kMinAlpha);
        measuredLobes_.push_back(std::make_unique<CarPaintBsdfLobe>(regularised));
        deltaLightLobe = measuredLobes_.back().get();
      }
    }
    materialLobe_.push_back(lobe);
    deltaLightMaterialLobe_.push_back(deltaLightLobe);
  }

  // Materials whose triangles carry vertex colours other than white (1, 1, 1, 1), which multiply the base
  // colour and coverage (materialAt): only these vary for their colours; white ones are the constant material.
  std::vector<uint8_t> coloured(rdb.materials.size(), 0);
  if (!rdb.colors.empty()) {
    for (uint32_t t = 0; t < rdb.triangleCount(); ++t) {
      for (uint32_t c = 0; c < 3; ++c) {
        if (rdb.colors[rdb.indices[3 * size_t{t} + c]] != vec4(1.0f)) coloured[rdb.triangleMaterial[t]] = 1;
      }
    }
  }
  frontBsdfs_.reserve(rdb.materials.size());
  backBsdfs_.reserve(rdb.materials.size());
  for (uint32_t mi = 0; mi < rdb.materials.size(); ++mi) {
    const rdb::TraceMaterial& m = rdb.materials[mi];
    // Partial coverage of a constant material is its opacity; cut-outs are opaque where rays hit them.
    const float coverage = m.alpha == rdb::TraceAlpha::kBlend ? m.opacity : 1.0f;
    frontBsdfs_.emplace_back(m, true, coverage, materialLobe_[mi]);
    backBsdfs_.emplace_back(m, m.doubleSided, coverage, materialLobe_[mi]);
    varies_.push_back(m.hasTextures() || coloured[mi] ? 1 : 0);
    hasClearGlass_ = hasClearGlass_ || frontBsdfs_.back().hasClearTransmission();
    const bool materialPasses =
        frontBsdfs_.back().passesStraight() || m.alpha == rdb::TraceAlpha::kBlend;
    passesStraight_ = passesStraight_ || materialPasses;
    // Whether a point of the material may pass light (its textures may make some points opaque).
    materialMayPass_.push_back(materialPasses ? 1 : 0);
    rdb::TraceMaterial regularised = m;
    if (!settings_.caustics) {
      regularised.reflectionGlossiness = std::max(m.reflectionGlossiness, kRegularizedGlossiness);
    }
    deltaLightFrontBsdfs_.emplace_back(regularised, true, coverage, deltaLightMaterialLobe_[mi]);
    deltaLightBackBsdfs_.emplace_back(regularised, m.doubleSided, coverage, deltaLightMaterialLobe_[mi]);
  }
  if (passesStraight_) {
    trianglePasses_.resize(rdb.triangleCount());
    for (uint32_t t = 0; t < rdb.triangleCount(); ++t) trianglePasses_[t] = materialMayPass_[rdb.triangleMaterial[t]];
    passThrough_ = {trianglePasses_.data(), &Integrator::paneTransmittance, this, kMaxPanesPassed};
  }
  if (std::any_of(rdb.materials.begin(), rdb.materials.end(),
                  [](const rdb::TraceMaterial& m) { return m.hasReflectionFog(); })) {
    fogBsdfs_.reserve(rdb.materials.size());
    for (const rdb::TraceMaterial& m : rdb.materials) {
      rdb::TraceMaterial fog;
      fog.diffuse = m.reflectionFogColor;
      fog.diffuseColor = m.reflectionFogColor;
      fogBsdfs_.emplace_back(fog, true);
    }
  }

  if (settings_.skyPortals && skyDistribution_ && (hasClearGlass_ || !rdb.portalCornersM.empty())) {
    buildPortals();
    if (!portalPlanes_.empty()) {
      vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
      for (const PortalPlane& q : portalPlanes_) {
        lo = glm::min(lo, q.boxMinM);
        hi = glm::max(hi, q.boxMaxM);
      }
      // Cells aligned with the boxes' low corner, a whole number of them in the margin.
      const float diagonalM = glm::length(hi - lo);
      portalCellSizeM_ = std::max(diagonalM / kPortalCellsAlongPortals, 1e-3f);
      const float marginCells = std::ceil(kPortalGridMargin * diagonalM / portalCellSizeM_);
      portalGridOriginM_ = lo - vec3(marginCells * portalCellSizeM_);
      portalGridCells_ = glm::uvec3(glm::ceil((hi - lo) / portalCellSizeM_)) + glm::uvec3(1 + 2 * uint32_t(marginCells));
      portalVisibility_ = std::make_unique<PortalVisibilityTable>(
          portalPlanes_.size(), size_t{portalGridCells_.x} * portalGridCells_.y * portalGridCells_.z);
      portalOutsideGrid_.assign(portalPlanes_.size(), 1.0f);
    }
  }

  std::vector<float> fluxesLm;
  for (uint32_t i = 0; i < rdb.punctualLights.size(); ++i) {
    const rdb::TracePunctualLight& light = rdb.punctualLights[i];
    const float intensityCd = std::max(luminance(light.intensity), 0.0f);
    switch (light.type) {
      case rdb::PunctualType::kDirectional:
        directionalLights_.push_back(i);
        continue;
      case rdb::PunctualType::kPoint:
        fluxesLm.push_back(4.0f * kPiF * intensityCd);
        break;
      case rdb::PunctualType::kSpot:
        fluxesLm.push_back(2.0f * kPiF * std::max(1.0f - light.cosOuter, 0.0f) * intensityCd);
        break;
      case rdb::PunctualType::kGoniometric: {
        // The table's mean: positive wherever the light shines, which is all the choice needs.
        const std::vector<float>& cd = rdb.goniometricTables[light.goniometricTable].candelaCd;
        double sum = 0.0;
        for (float c : cd) sum += std::max(c, 0.0f);
        fluxesLm.push_back(4.0f * kPiF * intensityCd *
                           static_cast<float>(sum / static_cast<double>(cd.size())));
        break;
      }
    }
    positionalLights_.push_back(i);
  }
  if (positionalLights_.size() > kAllPunctualLights) positionalDistribution_.emplace(fluxesLm);

  if (sunLights(rdb)) {
    // ∫ over the cone of half-angle θ_s of cos(angle to its axis) dω = π sin² θ_s; sin² θ_s = w (2 − w), w =
    // 1 − cos θ_s.
    sunOneMinusCos_ = oneMinusCos(rdb.sun.halfAngleRad);
    sunRadianceCdM2_ = rdb.sun.normalIlluminanceLux / (kPiF * sunOneMinusCos_ * (2.0f - sunOneMinusCos_));
    sunFrame_ = onb(rdb.sun.directionWorld);
  }

  if (settings_.litPatches && sunOneMinusCos_ > 0.0f) buildLitPatches();
}

uint32_t Integrator::skyCell(const vec3& d) const {
  const uint32_t res = rdb_.sky.resolution;
  const vec2 uv = skyUv(d);
  const auto i = std::min(static_cast<uint32_t>(uv.x * static_cast<float>(res)), res - 1);
  const auto j = std::min(static_cast<uint32_t>(uv.y * static_cast<float>(res)), res - 1);
  return j * res + i;
}

void Integrator::buildPortals() {
  // Clear-glass triangles and the declared portals' triangles (rdb.portalCornersM), grouped by plane: the same
  // normal up to ±, and every corner within a relative 10⁻⁵ of the plane. magnitudeM is the largest absolute
  // coordinate of the triangle's corners, for the ray offsets of the probe below.
  struct Candidate {
    uint32_t plane;
    float magnitudeM;
    Portal portal;
    float areaM2;
    bool declared;  // from rdb.portalCornersM
  };
  std::vector<Candidate> candidates;
  // Adds the triangle (p0, p0 + e1, p0 + e2) of unit normal n; false when kMaxPortalPlanes are exceeded.
  auto addCandidate = [&](const vec3& p0, const vec3& e1, const vec3& e2, const vec3& n, float areaM2,
                          float magnitudeM, bool declared) {
    const float e1e1 = glm::dot(e1, e1), e1e2 = glm::dot(e1, e2), e2e2 = glm::dot(e2, e2);
    const float denominator = e1e1 * e2e2 - e1e2 * e1e2;
    if (!(denominator > 0.0f)) return true;
    const float tolerance = 1e-5f * std::max(1.0f, magnitudeM);
    uint32_t plane = 0;
    for (; plane < portalPlanes_.size(); ++plane) {
      const PortalPlane& q = portalPlanes_[plane];
      auto off = [&](const vec3& x) { return std::abs(glm::dot(q.n, x) - q.offsetM); };
      if (std::abs(glm::dot(q.n, n)) > 1.0f - 1e-5f && off(p0) <= tolerance && off(p0 + e1) <= tolerance &&
          off(p0 + e2) <= tolerance) {
        break;
      }
    }
    if (plane == portalPlanes_.size()) {
      if (portalPlanes_.size() == kMaxPortalPlanes) return false;
      portalPlanes_.push_back({n, glm::dot(n, p0), p0, p0, 0, 0, 0.0f, n, 0.0f, 0.0f, p0, p0});
    }
    PortalPlane& q = portalPlanes_[plane];
    for (const vec3& x : {p0, p0 + e1, p0 + e2}) {
      q.boxMinM = glm::min(q.boxMinM, x);
      q.boxMaxM = glm::max(q.boxMaxM, x);
    }
    candidates.push_back(
        {plane, magnitudeM, {p0, e1, e2, n, 0.0f, e1e1, e1e2, e2e2, 1.0f / denominator}, areaM2, declared});
    return true;
  };
  // Beyond kMaxPortalPlanes there are no portals; a scene that declares some is told.
  auto tooManyPlanes = [&] {
    portalPlanes_.clear();
    if (!rdb_.portalCornersM.empty()) {
      log::warn("sky portals are off: the clear glass and the declared portals lie in more than " +
                std::to_string(kMaxPortalPlanes) + " planes");
    }
  };
  for (uint32_t t = 0; t < rdb_.triangleCount(); ++t) {
    if (!frontBsdfs_[rdb_.triangleMaterial[t]].hasClearTransmission() || !(scene_.triangleAreaM2(t) > 0.0f))
      continue;
    const vec3& p0 = rdb_.positionsM[rdb_.indices[3 * size_t{t}]];
    const vec3 e1 = rdb_.positionsM[rdb_.indices[3 * size_t{t} + 1]] - p0;
    const vec3 e2 = rdb_.positionsM[rdb_.indices[3 * size_t{t} + 2]] - p0;
    if (!addCandidate(p0, e1, e2, scene_.triangleNormal(t), scene_.triangleAreaM2(t),
                      scene_.triangleMagnitudeM(t), false)) {
      return tooManyPlanes();
    }
  }
  for (size_t i = 0; i + 2 < rdb_.portalCornersM.size(); i += 3) {
    const vec3& p0 = rdb_.portalCornersM[i];
    const vec3 e1 = rdb_.portalCornersM[i + 1] - p0;
    const vec3 e2 = rdb_.portalCornersM[i + 2] - p0;
    const vec3 twiceArea = glm::cross(e1, e2);
    const float twiceAreaM2 = glm::length(twiceArea);
    if (!(twiceAreaM2 > 0.0f)) continue;
    const float magnitudeM =
        std::max({maxAbs(p0), maxAbs(rdb_.portalCornersM[i + 1]), maxAbs(rdb_.portalCornersM[i + 2])});
    if (!addCandidate(p0, e1, e2, twiceArea / twiceAreaM2, 0.5f * twiceAreaM2, magnitudeM, true)) {
      return tooManyPlanes();
    }
  }
  // Each plane's inner side: rays from its panes' centres over the upper hemisphere on each side; the side
  // whose rays reach the sky less often, when the other's reach it at least 20 % of the time and at least
  // twice as often. Other planes (glass between rooms, glass in the open) are no portals.
  std::vector<bool> keep(portalPlanes_.size(), false);
  constexpr int kSphereDirections = 128;
  constexpr size_t kPanesTried = 8;
  uint64_t rays = 0;
  // Calls f(origin, d) for rays from the centres of up to kPanesTried of the panes, moved off to the side of
  // `side`, in the directions on that side of a Fibonacci sphere of kSphereDirections (equal-area; the
  // golden angle between consecutive points).
  auto probe = [&](const std::vector<const Candidate*>& panes, const vec3& side, auto&& f) {
    const size_t tried = std::min(kPanesTried, panes.size());
    for (size_t k = 0; k < tried; ++k) {
      const Candidate& c = *panes[k * panes.size() / tried];
      const vec3 origin =
          offsetRayOrigin(c.portal.p0 + (c.portal.e1 + c.portal.e2) / 3.0f, side, c.magnitudeM);
      for (int i = 0; i < kSphereDirections; ++i) {
        const float y = 1.0f - (2.0f * static_cast<float>(i) + 1.0f) / kSphereDirections;
        const float r = std::sqrt(std::max(0.0f, 1.0f - y * y));
        const float phi = 2.39996323f * static_cast<float>(i);
        const vec3 d(r * std::cos(phi), y, r * std::sin(phi));
        if (glm::dot(d, side) > 0.0f) f(origin, d);
      }
    }
  };
  for (uint32_t plane = 0; plane < portalPlanes_.size(); ++plane) {
    PortalPlane& q = portalPlanes_[plane];
    std::vector<const Candidate*> panes;
    for (const Candidate& c : candidates)
      if (c.plane == plane) panes.push_back(&c);
    float skyFraction[2] = {0.0f, 0.0f};
    for (int side = 0; side < 2; ++side) {
      int tried = 0, escaped = 0;
      probe(panes, side == 0 ? q.n : -q.n, [&](const vec3& origin, const vec3& d) {
        if (!(d.y > 0.0f)) return;
        ++tried;
        if (maxComponent(visibility(origin, d, std::numeric_limits<float>::infinity(), rays)) > 0.0f)
          ++escaped;
      });
      skyFraction[side] = tried > 0 ? static_cast<float>(escaped) / static_cast<float>(tried) : 0.0f;
    }
    const int outer = skyFraction[0] >= skyFraction[1] ? 0 : 1;
    if (skyFraction[outer] < 0.2f || skyFraction[1 - outer] > 0.5f * skyFraction[outer]) {
      if (std::any_of(panes.begin(), panes.end(), [](const Candidate* c) { return c->declared; })) {
        const vec3 centreM = 0.5f * (q.boxMinM + q.boxMaxM);
        char message[320];
        std::snprintf(message, sizeof message,
                      "the declared sky portal in the plane through (%.3f, %.3f, %.3f) m is not used: %.0f %% "
                      "and %.0f %% of the rays from its two sides reach the sky; a portal serves an opening "
                      "between an enclosed interior and the sky",
                      centreM.x, centreM.y, centreM.z, 100.0f * skyFraction[outer],
                      100.0f * skyFraction[1 - outer]);
        log::warn(message);
      }
      continue;
    }
    keep[plane] = true;
    q.inward = outer == 0 ? -q.n : q.n;
    // The depth of the room behind: the farthest hit of rays from the panes into it (unbounded when one
    // escapes).
    float depthM = 0.0f;
    probe(panes, q.inward, [&](const vec3& origin, const vec3& d) {
      const std::optional<Hit> hit = scene_.intersect(origin, d, std::numeric_limits<float>::infinity());
      depthM = hit ? std::max(depthM, hit->distanceM) : std::numeric_limits<float>::infinity();
    });
    const vec3 grow(std::min(depthM, 1e30f));
    q.regionMinM = q.boxMinM - grow;
    q.regionMaxM = q.boxMaxM + grow;
  }

  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Candidate& a, const Candidate& b) { return a.plane < b.plane; });
  std::vector<PortalPlane> planes;
  uint32_t lastPlane = ~0u;
  for (const Candidate& c : candidates) {
    if (!keep[c.plane]) continue;
    if (c.plane != lastPlane) {
      lastPlane = c.plane;
      planes.push_back(portalPlanes_[c.plane]);
      planes.back().first = static_cast<uint32_t>(portals_.size());
    }
    PortalPlane& q = planes.back();
    ++q.count;
    q.areaM2 += c.areaM2;
    portals_.push_back(c.portal);
    portals_.back().cumulativeAreaM2 = q.areaM2;
  }
  for (PortalPlane& q : planes) {
    const float marginM = 1e-5f * std::max({1.0f, maxAbs(q.boxMinM), maxAbs(q.boxMaxM)});
    // The boxes a little larger, so that a point on an edge is inside.
    q.boxMinM -= vec3(marginM);
    q.boxMaxM += vec3(marginM);
    q.inwardOffsetM = glm::dot(q.inward, portals_[q.first].p0);
    q.insideMarginM = marginM;
    buildPortalGrid(q, marginM);
  }
  if (!portalCellStart_.empty()) portalCellStart_.push_back(static_cast<uint32_t>(portalCellItems_.size()));
  portalPlanes_ = std::move(planes);
}

void Integrator::buildPortalGrid(PortalPlane& q, float marginM) {
  // Planes of many panes (a glazed facade) get a grid of about one pane per cell, so that a density
  // evaluation tests the panes of one cell rather than all.
  if (q.count <= kPanesWithoutGrid) return;
  q.origin = portals_[q.first].p0;
  q.axisU = glm::normalize(portals_[q.first].e1);
  q.axisV = glm::normalize(glm::cross(q.n, q.axisU));
  auto local = [&](const vec3& x) {
    return vec2(glm::dot(x - q.origin, q.axisU), glm::dot(x - q.origin, q.axisV));
  };
  // The box of a pane, or of all, in the plane's coordinates.
  auto box = [&](uint32_t first, uint32_t last, vec2& lo, vec2& hi) {
    lo = vec2(std::numeric_limits<float>::max());
    hi = vec2(-std::numeric_limits<float>::max());
    for (uint32_t j = first; j < last; ++j) {
      const Portal& p = portals_[j];
      for (const vec3& x : {p.p0, p.p0 + p.e1, p.p0 + p.e2}) {
        lo = glm::min(lo, local(x));
        hi = glm::max(hi, local(x));
      }
    }
  };
  vec2 lo, hi;
  box(q.first, q.first + q.count, lo, hi);
  q.cells = std::clamp(static_cast<uint32_t>(std::ceil(std::sqrt(static_cast<float>(q.count)))), 1u, 256u);
  q.gridMinM = lo - vec2(marginM);
  q.cellsPerM = static_cast<float>(q.cells) / (std::max(hi.x - lo.x, hi.y - lo.y) + 2.0f * marginM);
  q.firstCell = static_cast<uint32_t>(portalCellStart_.size());
  const uint32_t planeCells = q.cells * q.cells;
  // Counting sort of (cell, pane) pairs: counts, prefix sums, then the items.
  auto forCells = [&](uint32_t j, auto&& f) {
    vec2 a, b;
    box(j, j + 1, a, b);
    const glm::uvec2 c0 = cellOf(q, a - vec2(marginM));
    const glm::uvec2 c1 = cellOf(q, b + vec2(marginM));
    for (uint32_t cy = c0.y; cy <= c1.y; ++cy)
      for (uint32_t cx = c0.x; cx <= c1.x; ++cx) f(cy * q.cells + cx);
  };
  std::vector<uint32_t> counts(planeCells, 0);
  for (uint32_t j = q.first; j < q.first + q.count; ++j) forCells(j, [&](uint32_t c) { ++counts[c]; });
  auto start = static_cast<uint32_t>(portalCellItems_.size());
  std::vector<uint32_t> fill(planeCells);
  for (uint32_t c = 0; c < planeCells; ++c) {
    portalCellStart_.push_back(start);
    fill[c] = start;
    start += counts[c];
  }
  portalCellItems_.resize(start);
  for (uint32_t j = q.first; j < q.first + q.count; ++j) {
    forCells(j, [&](uint32_t c) { portalCellItems_[fill[c]++] = j; });
  }
}

glm::uvec2 Integrator::cellOf(const PortalPlane& q, const vec2& localM) {
  const vec2 c = glm::floor((localM - q.gridMinM) * q.cellsPerM);
  const auto clampCell = [&](float v) {
    return static_cast<uint32_t>(std::clamp(v, 0.0f, static_cast<float>(q.cells - 1)));
  };
  return glm::uvec2(clampCell(c.x), clampCell(c.y));
}

bool Integrator::insidePortal(const vec3& x, uint32_t q) const {
  const PortalPlane& plane = portalPlanes_[q];
  return glm::dot(plane.inward, x) > plane.inwardOffsetM + plane.insideMarginM &&
         !glm::any(glm::lessThan(x, plane.regionMinM)) && !glm::any(glm::greaterThan(x, plane.regionMaxM));
}

float Integrator::portalContinuationShare(const vec3& x, float& weight) const {
  // The panes' area below x's height, for each plane the share of its box's height below x (exact for
  // upright rectangular windows), weighted as portalPoint() chooses the planes.
  float below = 0.0f;
  weight = 0.0f;
  const float* visibility = nullptr;
  for (uint32_t q = 0; q < portalPlanes_.size(); ++q) {
    if (!insidePortal(x, q)) continue;
    const PortalPlane& plane = portalPlanes_[q];
    if (!visibility) visibility = portalVisibilityAt(x);
    const float w = portalPlaneWeight(x, q, visibility);
    weight += w;
    const float heightM = plane.boxMaxM.y - plane.boxMinM.y;
    const float share = heightM > 0.0f ? std::clamp((x.y - plane.boxMinM.y) / heightM, 0.0f, 1.0f)
                                       : (x.y > plane.boxMinM.y ? 1.0f : 0.0f);
    below += share * w;
  }
  return weight > 0.0f ? kPortalContinuationFraction * below / weight : 0.0f;
}

float Integrator::portalPlaneWeight(const vec3& x, uint32_t q, const float* visibility) const {
  const PortalPlane& plane = portalPlanes_[q];
  const vec3 toCentre = 0.5f * (plane.boxMinM + plane.boxMaxM) - x;
  const float t2 = glm::dot(toCentre, toCentre);
  const float cosTheta =
      t2 > 0.0f ? std::max(kPortalMinCosine, std::abs(glm::dot(plane.n, toCentre)) / std::sqrt(t2)) : 1.0f;
  return plane.areaM2 * cosTheta / (t2 + plane.areaM2 * (1.0f / kPiF)) * (kPortalVisibilityFloor + visibility[q]);
}

float Integrator::portalWeight(const vec3& x) const {
  float weight = 0.0f;
  const float* visibility = nullptr;
  for (uint32_t q = 0; q < portalPlanes_.size(); ++q) {
    if (!insidePortal(x, q)) continue;
    if (!visibility) visibility = portalVisibilityAt(x);
    weight += portalPlaneWeight(x, q, visibility);
  }
  return weight;
}

// The visibility table: open addressing with linear probing over a power-of-two number of slots (at least
// twice the grid's cells, at most kMaxShareBytes of shares) of a key (the cell's index in the grid, kEmpty
// where free) and a ready flag, and per slot one share per portal plane.
struct Integrator::PortalVisibilityTable {
  static constexpr uint64_t kEmpty = std::numeric_limits<uint64_t>::max();
  static constexpr size_t kMaxProbes = 64;
  static constexpr size_t kMaxShareBytes = size_t{64} << 20;
  struct Slot {
    std::atomic<uint64_t> key{kEmpty};
    std::atomic<uint32_t> ready{0};
  };
  PortalVisibilityTable(size_t planeCount, size_t cells)
      : planes(planeCount),
        slots(std::clamp(std::bit_ceil(2 * cells), size_t{1024},
                         std::bit_floor(std::max(size_t{1024}, kMaxShareBytes / sizeof(float) / planeCount)))),
        shares(slots.size() * planeCount) {}
  size_t planes;
  std::vector<Slot> slots;
  std::vector<float> shares;
};

Integrator::~Integrator() = default;

const float* Integrator::portalVisibilityAt(const vec3& x) const {
  const vec3 c = glm::floor((x - portalGridOriginM_) / portalCellSizeM_);
  if (!(glm::all(glm::greaterThanEqual(c, vec3(0.0f))) && glm::all(glm::lessThan(c, vec3(portalGridCells_)))))
    return portalOutsideGrid_.data();
  const glm::ivec3 cell(c);
  const uint64_t key =
      (uint64_t(uint32_t(cell.x)) * portalGridCells_.y + uint32_t(cell.y)) * portalGridCells_.z + uint32_t(cell.z);
  PortalVisibilityTable& table = *portalVisibility_;
  const size_t mask = table.slots.size() - 1;
  // SplitMix64's finaliser as the hash (Steele, Lea & Flood, "Fast splittable pseudorandom number
  // generators", OOPSLA 2014).
  uint64_t h = key;
  h = (h ^ (h >> 30)) * 0xbf58476d1ce4e5b9ull;
  h = (h ^ (h >> 27)) * 0x94d049bb133111ebull;
  h ^= h >> 31;
  for (size_t probe = 0; probe < PortalVisibilityTable::kMaxProbes; ++probe) {
    const size_t slot = (h + probe) & mask;
    PortalVisibilityTable::Slot& s = table.slots[slot];
    float* shares = table.shares.data() + slot * table.planes;
    uint64_t k = s.key.load(std::memory_order_acquire);
    if (k == PortalVisibilityTable::kEmpty &&
        s.key.compare_exchange_strong(k, key, std::memory_order_acq_rel, std::memory_order_acquire)) {
      computePortalVisibility(cell, shares);
      s.ready.store(1, std::memory_order_release);
      return shares;
    }
    if (k == key) {
      if (s.ready.load(std::memory_order_acquire)) return shares;
      break;
    }
  }
  // Still being filled, or the table is full around this key: the same values, computed here.
  thread_local std::vector<float> own;
  own.resize(table.planes);
  computePortalVisibility(cell, own.data());
  return own.data();
}

void Integrator::computePortalVisibility(const glm::ivec3& cell, float* out) const {
  // Points and pane points from the Hammersley set (Pharr, Jakob & Humphreys, "Physically Based
  // Rendering", 4th ed., ch. 8): i / n and radical inverses in bases 2 and 3.
  auto radicalInverse = [](uint32_t i, uint32_t base) {
    float inverse = 1.0f / static_cast<float>(base), f = inverse, r = 0.0f;
    for (; i > 0; i /= base, f *= inverse) r += f * static_cast<float>(i % base);
    return r;
  };
  uint64_t rays = 0;
  for (uint32_t q = 0; q < portalPlanes_.size(); ++q) {
    uint32_t reached = 0;
    for (uint32_t o = 0; o < kPortalVisibilityOrigins; ++o) {
      const vec3 inCell((static_cast<float>(o) + 0.5f) / kPortalVisibilityOrigins, radicalInverse(o + 1, 2),
                        radicalInverse(o + 1, 3));
      const vec3 origin = portalGridOriginM_ + (vec3(cell) + inCell) * portalCellSizeM_;
      for (uint32_t k = 0; k < kPortalVisibilityRays; ++k) {
        const vec2 u((static_cast<float>(k) + 0.5f) / kPortalVisibilityRays, radicalInverse(k + 1, 2));
        const vec3 toPane = planePoint(q, u) - origin;
        const float distM = glm::length(toPane);
        if (!(distM > 0.0f)) continue;
        if (maxComponent(visibility(origin, toPane / distM, distM * (1.0f - 1e-4f), rays)) > 0.0f) ++reached;
      }
    }
    out[q] = static_cast<float>(reached) / static_cast<float>(kPortalVisibilityOrigins * kPortalVisibilityRays);
  }
}

float Integrator::portalPdf(const vec3& x, const vec3& d, float weight) const {
  float pdf = 0.0f;  // Σ over the planes met of P(plane) t² / (A_plane |cos θ|) for the panes met
  const float* visibility = nullptr;
  for (uint32_t qi = 0; qi < portalPlanes_.size(); ++qi) {
    if (!insidePortal(x, qi)) continue;
    const PortalPlane& q = portalPlanes_[qi];
    const float t = (q.offsetM - glm::dot(q.n, x)) / glm::dot(q.n, d);
    if (!(t > 0.0f) || !std::isfinite(t)) continue;
    const vec3 y = x + t * d;
    if (glm::any(glm::lessThan(y, q.boxMinM)) || glm::any(glm::greaterThan(y, q.boxMaxM))) continue;
    // The panes to test: all, or those of the grid cell under y.
    const uint32_t* items = nullptr;
    uint32_t itemCount = q.count;
    if (q.cells > 0) {
      const glm::uvec2 c = cellOf(q, vec2(glm::dot(y - q.origin, q.axisU), glm::dot(y - q.origin, q.axisV)));
      const uint32_t cell = q.firstCell + c.y * q.cells + c.x;
      items = portalCellItems_.data() + portalCellStart_[cell];
      itemCount = portalCellStart_[cell + 1] - portalCellStart_[cell];
    }
    float sum = 0.0f;  // Σ t² / |cos θ| over the plane's panes met
    for (uint32_t k = 0; k < itemCount; ++k) {
      const Portal& p = portals_[items ? items[k] : q.first + k];
      // Barycentrics of y in the triangle's plane (Ericson, "Real-Time Collision Detection", 2005, §3.4).
      const vec3 r = y - p.p0;
      const float re1 = glm::dot(r, p.e1), re2 = glm::dot(r, p.e2);
      const float b1 = (p.e2e2 * re1 - p.e1e2 * re2) * p.invDenominator;
      const float b2 = (p.e1e1 * re2 - p.e1e2 * re1) * p.invDenominator;
      if (!(b1 >= -1e-6f && b2 >= -1e-6f && b1 + b2 <= 1.0f + 1e-6f)) continue;
      const float cosPane = std::abs(glm::dot(p.n, d));
      if (cosPane > 0.0f) sum += t * t / cosPane;
    }
    if (sum > 0.0f) {
      if (!visibility) visibility = portalVisibilityAt(x);
      pdf += portalPlaneWeight(x, qi, visibility) / (weight * q.areaM2) * sum;
    }
  }
  return std::isfinite(pdf) ? pdf : 0.0f;
}

float Integrator::skyLightPdf(const vec3& x, const vec3& d, uint32_t cell, float portalWeight,
                              float portalFraction) const {
  const float table = skyPdfPerSr_[cell];
  if (!(portalWeight > 0.0f)) return table;
  return (1.0f - portalFraction) * table + portalFraction * portalPdf(x, d, portalWeight);
}

Integrator::PointBsdfs Integrator::bsdfsAt(uint32_t mi, bool front, const TrianglePoint& at,
                                           std::optional<Bsdf>& point,
                                           std::optional<Bsdf>& pointDeltaLight) const {
  const rdb::TraceMaterial& m = rdb_.materials[mi];
  const bool frontFace = front || m.doubleSided;
  if (!varies_[mi]) {
    return {frontFace ? &frontBsdfs_[mi] : &backBsdfs_[mi],
            frontFace ? &deltaLightFrontBsdfs_[mi] : &deltaLightBackBsdfs_[mi]};
  }
  PointMaterial pm = materialAt(rdb_, m, at);
  const float coverage = m.alpha == rdb::TraceAlpha::kBlend ? pm.coverage : 1.0f;
  point.emplace(pm.material, frontFace, coverage, materialLobe_[mi]);
  if (!settings_.caustics) {
    pm.material.reflectionGlossiness = std::max(pm.material.reflectionGlossiness, kRegularizedGlossiness);
  }
  pointDeltaLight.emplace(pm.material, frontFace, coverage, deltaLightMaterialLobe_[mi]);
  return {&*point, &*pointDeltaLight};
}

float Integrator::emitterPdf(uint32_t t, float distM, float absCosLight) const {
  if (absCosLight <= 0.0f) return 0.0f;
  return emitterPmfOfTriangle_[t] / scene_.triangleAreaM2(t) * distM * distM / absCosLight;
}

vec3 Integrator::hitPoint(const Hit& hit) const {
  const uint32_t t = hit.triangle;
  const vec3& p0 = rdb_.positionsM[rdb_.indices[3 * t]];
  const vec3& p1 = rdb_.positionsM[rdb_.indices[3 * t + 1]];
  const vec3& p2 = rdb_.positionsM[rdb_.indices[3 * t + 2]];
  return (1.0f - hit.barycentric.x - hit.barycentric.y) * p0 + hit.barycentric.x * p1 +
         hit.barycentric.y * p2;
}

Rgb Integrator::visibility(const vec3& origin, const vec3& dir, float tMaxM, uint64_t& rays) const {
  ++rays;
  if (!passesStraight_) return scene_.occluded(origin, dir, tMaxM) ? Rgb(0.0f) : Rgb(1.0f);
  return scene_.transmittance(origin, dir, tMaxM, passThrough_);
}

Rgb Integrator::paneTransmittance(const void* user, const Hit& hit, const vec3& dir) {
  const auto& self = *static_cast<const Integrator*>(user);
  const uint32_t mi = self.rdb_.triangleMaterial[hit.triangle];
  std::optional<Bsdf> point, pointDeltaLight;
  const Bsdf& pane = *self.bsdfsAt(mi, true, {hit.triangle, hit.barycentric}, point, pointDeltaLight).bsdf;
  if (!pane.passesStraight()) return Rgb(0.0f);
  return pane.straightTransmittance(std::abs(glm::dot(hit.geometricNormal, dir)));
}

bool Integrator::response(const Vertex& v, const Bsdf* bsdf, const vec3& d, Rgb& fCos, float& pdf,
                          float distM) const {
  const float cosTheta = glm::dot(v.n, d);
  if (bsdf == nullptr) {
    if (!(cosTheta > 0.0f)) return false;
    fCos = Rgb(cosTheta);
    pdf = continuationPdf(v, cosTheta, d);
    return true;
  }
  // The geometric side decides which side light arrives on; the shading normal must agree.
  const float cosGeometric = glm::dot(v.ng, d);
  if (cosGeometric == 0.0f || (cosGeometric > 0.0f) != (cosTheta > 0.0f)) return false;
  if (bsdf->isLambertian()) {
    if (!(cosTheta > 0.0f)) return false;
    fCos = bsdf->lambertAlbedo() * (cosTheta / kPiF);
    pdf = continuationPdf(v, cosTheta, d);
    return true;
  }
  if (!(cosTheta > 0.0f) && !(cosTheta < 0.0f && bsdf->hasNonDeltaTransmission())) return false;
  const vec3 wi = v.frame.toLocal(d);
  Rgb f = bsdf->eval(v.woLocal, wi);
  if (v.fogBsdf) f = glm::max(f - fogFraction(distM, v.fogDistanceM) * bsdf->evalReflection(v.woLocal, wi), 0.0f);
  fCos = f * std::abs(cosTheta);
  if (!(maxComponent(fCos) > 0.0f)) return false;
  pdf = bsdf->pdf(v.woLocal, wi);
  return true;
}

float Integrator::continuationPdf(const Vertex& v, float cosTheta, const vec3& d) const {
  const float cosine = cosineHemispherePdf(cosTheta);
  if (!(v.portalShare > 0.0f)) return cosine;
  return (1.0f - v.portalShare) * cosine + v.portalShare * portalPdf(v.p, d, v.portalWeight);
}

bool Integrator::sampleContinuation(const Vertex& v, vec2 u, vec3& d, float& cosTheta, float& pdf) const {
  if (v.portalShare > 0.0f && u.x < v.portalShare) {
    const vec3 toPortal = portalPoint(v.p, v.portalWeight, vec2(u.x / v.portalShare, u.y)) - v.p;
    const float distM = glm::length(toPortal);
    if (!(distM > 0.0f)) return false;
    d = toPortal / distM;
  } else {
    if (v.portalShare > 0.0f) u.x = std::min((u.x - v.portalShare) / (1.0f - v.portalShare), 0x1.fffffep-1f);
    d = glm::normalize(v.frame.toWorld(sampleCosineHemisphere(u)));
  }
  cosTheta = glm::dot(v.n, d);
  if (!(cosTheta > 0.0f)) return false;
  pdf = continuationPdf(v, cosTheta, d);
  return pdf > 0.0f && std::isfinite(pdf);
}

vec3 Integrator::portalPoint(const vec3& x, float weight, const vec2& u) const {
  // u.x rescaled to the weight of x's portal planes chooses the plane; what remains, rescaled to [0, 1),
  // and u.y the point on it.
  float target = std::min(u.x, 0x1.fffffep-1f) * weight;
  uint32_t plane = ~0u;
  float planeWeight = 0.0f;
  const float* visibility = portalVisibilityAt(x);
  for (uint32_t q = 0; q < portalPlanes_.size(); ++q) {
    if (!insidePortal(x, q)) continue;
    plane = q;
    planeWeight = portalPlaneWeight(x, q, visibility);
    if (target < planeWeight) break;
    target -= planeWeight;
  }
  return planePoint(plane, vec2(std::clamp(target / planeWeight, 0.0f, 0x1.fffffep-1f), u.y));
}

vec3 Integrator::planePoint(uint32_t plane, const vec2& u) const {
  // u.x rescaled to the plane's area chooses the pane and, with what remains and u.y, the point on it.
  const PortalPlane& q = portalPlanes_[plane];
  const float target = u.x * q.areaM2;
  const auto first = portals_.begin() + q.first;
  const auto last = first + q.count;
  auto pane = std::upper_bound(first, last, target, [](float a, const Portal& p) { return a < p.cumulativeAreaM2; });
  if (pane == last) --pane;
  const float start = pane == first ? 0.0f : (pane - 1)->cumulativeAreaM2;
  const float paneArea = pane->cumulativeAreaM2 - start;
  const float ux = std::clamp((target - start) / paneArea, 0.0f, 0x1.fffffep-1f);
  const vec3 b = sampleUniformTriangle(vec2(ux, u.y));
  return pane->p0 + b.y * pane->e1 + b.z * pane->e2;
}

Rgb Integrator::deltaDirectIrradiance(const vec3& p, const vec3& n, uint64_t& rays,
                                      float surfaceMagnitudeM) const {
  const Vertex v{p, n, n, std::max(maxAbs(p), surfaceMagnitudeM), nullptr, nullptr, onb(n), vec3(0.0f)};
  Rgb sum(0.0f);
  if (sunOneMinusCos_ > 0.0f) {
    const vec3& toSun = rdb_.sun.directionWorld;
    const float cosTheta = glm::dot(n, toSun);
    if (cosTheta > 0.0f) {
      const vec3 origin = offsetRayOrigin(p, n, v.magnitudeM);
      sum += rdb_.sun.normalIlluminanceLux * cosTheta *
             visibility(origin, toSun, std::numeric_limits<float>::infinity(), rays);
    }
  }
  for (const rdb::TracePunctualLight& light : rdb_.punctualLights) sum += punctualLight(light, v, rays);
  return sum;
}

Rgb Integrator::punctualLight(const rdb::TracePunctualLight& light, const Vertex& v, uint64_t& rays) const {
  Rgb fCos;
  float pdfUnused;
  if (light.type == rdb::PunctualType::kDirectional) {
    const vec3 toLight = -light.directionWorld;
    if (!response(v, v.deltaLightBsdf, toLight, fCos, pdfUnused)) return Rgb(0.0f);
    const vec3 origin = offsetRayOrigin(v.p, glm::dot(v.ng, toLight) > 0.0f ? v.ng : -v.ng, v.magnitudeM);
    return light.intensity * fCos * visibility(origin, toLight, std::numeric_limits<float>::infinity(), rays);
  }
  const vec3 toLight = light.positionM - v.p;
  const float distM = glm::length(toLight);
  if (!(distM > 0.0f) || distM >= light.rangeM) return Rgb(0.0f);
  const vec3 dir = toLight / distM;
  if (!response(v, v.deltaLightBsdf, dir, fCos, pdfUnused, distM)) return Rgb(0.0f);
  // KHR_lights_punctual's recommended range window: clamp(1 − (d / range)⁴, 0, 1) / d².
  const float ratio = distM / light.rangeM;
  float factor = std::clamp(1.0f - ratio * ratio * ratio * ratio, 0.0f, 1.0f);
  if (light.type == rdb::PunctualType::kSpot) {
    factor *= spotConeAttenuation(glm::dot(light.directionWorld, -dir), light.cosInner, light.cosOuter);
  } else if (light.type == rdb::PunctualType::kGoniometric) {
    // γ from the photometric axis (directionWorld), C from cAxisWorld towards the light's +Y = −Z × X.
    const vec3 w = -dir;
    const float gamma = std::acos(std::clamp(glm::dot(w, light.directionWorld), -1.0f, 1.0f));
    const vec3 yAxis = glm::cross(-light.directionWorld, light.cAxisWorld);
    const float c = std::atan2(glm::dot(w, yAxis), glm::dot(w, light.cAxisWorld));
    factor *= goniometricCandela(rdb_.goniometricTables[light.goniometricTable], gamma, c);
  }
  if (factor <= 0.0f) return Rgb(0.0f);
  const vec3 origin = offsetRayOrigin(v.p, glm::dot(v.ng, dir) > 0.0f ? v.ng : -v.ng, v.magnitudeM);
  return light.intensity * fCos * (factor / (distM * distM)) * visibility(origin, dir, distM, rays);
}

template <class S>
Rgb Integrator::directLight(const Vertex& v, bool allLights, uint32_t group, const vec2& uEmitter,
                            float uPunctual, S& sampler, uint64_t& rays, Rgb* sunPart, Rgb* sunSkyPart,
                            bool sunSkyOnly) const {
  sampler.startGroup(group);
  Rgb sum(0.0f);
  // The ray origin on the side of the light.
  auto originTowards = [&](const vec3& d) {
    return offsetRayOrigin(v.p, glm::dot(v.ng, d) > 0.0f ? v.ng : -v.ng, v.magnitudeM);
  };
  Rgb fCos;
  float pdfBsdf;

  if (sunOneMinusCos_ > 0.0f) {
    // Uniform in the sun's cone: L f |cos θ| / pdf, pdf = 1 / (2π (1 − cos θ_s)).
    const vec3 d = sunFrame_.toWorld(sampleUniformCone(sampler.next2D(), sunOneMinusCos_));
    if (response(v, v.deltaLightBsdf, d, fCos, pdfBsdf)) {
      sum += sunRadianceCdM2_ * fCos * (1.0f / uniformConePdf(sunOneMinusCos_)) *
             visibility(originTowards(d), d, std::numeric_limits<float>::infinity(), rays);
    }
    if (sunPart) *sunPart = sum;
  }

  if (skyDistribution_ && allLights) {
    if (sunOneMinusCos_ <= 0.0f) sampler.skip(2);
    vec2 u = sampler.next2D();
    // The portals' share α where v is inside some portal plane, else 0.
    const float portalWeightAtV = portalWeight(v.p);
    const float alpha = portalWeightAtV > 0.0f ? (v.bsdf ? kPortalFraction : kSensorPortalFraction) : 0.0f;
    std::optional<vec3> d;
    uint32_t cell = 0;
    float tablePdf = 0.0f;  // with portals, the mixture's density is computed once the direction is seen
    if (u.x < alpha) {
      // Through a portal: a point on the panes of v's portal planes (portalPoint).
      const vec3 toPortal = portalPoint(v.p, portalWeightAtV, vec2(u.x / alpha, u.y)) - v.p;
      const float distM = glm::length(toPortal);
      // The sky is above the horizon only (TraceSky); directions below it find no sky light.
      if (distM > 0.0f && toPortal.y > 0.0f) {
        d = toPortal / distM;
        cell = skyCell(*d);
      }
    } else {
      if (alpha > 0.0f) u.x = std::min((u.x - alpha) / (1.0f - alpha), 0x1.fffffep-1f);
      const Distribution2D::Sample s = skyDistribution_->sample(u);
      d = skyDirection(s.p);
      cell = s.cell;
      tablePdf = s.pdf / (2.0f * kPiF);
    }
    if (d && (alpha > 0.0f || tablePdf > 0.0f) && response(v, v.bsdf, *d, fCos, pdfBsdf)) {
      const Rgb seen = visibility(originTowards(*d), *d, std::numeric_limits<float>::infinity(), rays);
      if (maxComponent(seen) > 0.0f) {
        const float pdf = alpha > 0.0f ? skyLightPdf(v.p, *d, cell, portalWeightAtV, alpha) : tablePdf;
        if (pdf > 0.0f && std::isfinite(pdf)) {
          sum += rdb_.sky.radianceCdM2[cell] * fCos * (powerHeuristic(pdf, pdfBsdf) / pdf) * seen;
        }
      }
    }
  }
  if (sunSkyPart) *sunSkyPart = sum;
  if (sunSkyOnly) return sum;

  for (uint32_t i : directionalLights_) sum += punctualLight(rdb_.punctualLights[i], v, rays);
  if (positionalDistribution_) {
    const Distribution1D::DiscreteSample pick = positionalDistribution_->sampleDiscrete(uPunctual);
    sum += punctualLight(rdb_.punctualLights[positionalLights_[pick.index]], v, rays) / pick.pmf;
  } else {
    for (uint32_t i : positionalLights_) sum += punctualLight(rdb_.punctualLights[i], v, rays);
  }

  if (emitterDistribution_ && allLights) {
    const Distribution1D::DiscreteSample pick = emitterDistribution_->sampleDiscrete(uEmitter.x);
    const uint32_t t = rdb_.emissiveTriangles[pick.index];
    const vec3 b = sampleUniformTriangle(vec2(pick.uRemapped, uEmitter.y));
    const vec3& p0 = rdb_.positionsM[rdb_.indices[3 * t]];
    const vec3& p1 = rdb_.positionsM[rdb_.indices[3 * t + 1]];
    const vec3& p2 = rdb_.positionsM[rdb_.indices[3 * t + 2]];
    const vec3 y = b.x * p0 + b.y * p1 + b.z * p2;
    const vec3 toLight = y - v.p;
    const float distM = glm::length(toLight);
    const vec3 d = toLight / distM;
    const vec3& nLight = scene_.triangleNormal(t);
    const float cosLight = -glm::dot(nLight, d);
    const rdb::TraceMaterial& m = rdb_.materials[rdb_.triangleMaterial[t]];
    if (distM > 0.0f && (cosLight > 0.0f || (m.doubleSided && cosLight < 0.0f)) &&
        response(v, v.bsdf, d, fCos, pdfBsdf, distM)) {
      const float pdf = emitterPdf(t, distM, std::abs(cosLight));
      // Both ends moved off their surfaces, the light's towards the receiver.
      const vec3 origin = originTowards(d);
      const vec3 target =
          offsetRayOrigin(y, cosLight > 0.0f ? nLight : -nLight, scene_.triangleMagnitudeM(t));
      const vec3 toTarget = target - origin;
      const float targetDistM = glm::length(toTarget);
      if (pdf > 0.0f && std::isfinite(pdf) && targetDistM > 0.0f) {
        sum += emissionAt(rdb_, m, {t, vec2(b.y, b.z)}) * fCos * (powerHeuristic(pdf, pdfBsdf) / pdf) *
               visibility(origin, toTarget / targetDistM, targetDistM, rays);
      }
    }
  }
  return sum;
}

float Integrator::patchWeight(float pdfPatch, float pdfPath) const {
  switch (settings_.litPatchWeights) {
    case IntegratorSettings::LitPatchWeights::kPatchesOnly:
      return 1.0f;
    case IntegratorSettings::LitPatchWeights::kPathsOnly:
      return 0.0f;
    case IntegratorSettings::LitPatchWeights::kPowerHeuristic:
      break;
  }
  return powerHeuristic(pdfPatch, pdfPath);
}

std::optional<Integrator::Vertex> Integrator::vertexAt(const vec3& x, const TrianglePoint& at, const vec3& ng,
                                                      const vec3& d, std::optional<Bsdf>& point,
                                                      std::optional<Bsdf>& pointDeltaLight) const {
  const uint32_t t = at.triangle;
  const bool front = glm::dot(ng, d) < 0.0f;
  const uint32_t mi = rdb_.triangleMaterial[t];
  const PointBsdfs bsdfs = bsdfsAt(mi, front, at, point, pointDeltaLight);
  const vec3 side = front ? ng : -ng;
  const float cosGeometric = -glm::dot(side, d);
  if (!(cosGeometric > 0.0f)) return std::nullopt;
  // The shading normal on the side the ray came from. Where the direction back along the ray is below it
  // (an interpolated or mapped normal tilted away from the viewer), it is bent towards the geometric normal
  // until that direction is kMinShadingCos above it, so that no path finds a black surface (a facet of a
  // smooth low-poly mesh seen at a grazing angle).
  vec3 ns = shadingNormalAt(rdb_, rdb_.materials[mi], at, ng);
  if (!front) ns = -ns;
  const float cosShading = -glm::dot(ns, d);
  if (cosShading < kMinShadingCos) {
    ns = glm::normalize(ns + ((kMinShadingCos - cosShading) / cosGeometric) * side);
  }
  const Onb frame = shadingFrameAt(rdb_, rdb_.materials[mi], at, ns, front);
  const vec3 wo = frame.toLocal(-d);
  if (!(wo.z > 0.0f)) return std::nullopt;
  Vertex v{x, ns, side, std::max(maxAbs(x), scene_.triangleMagnitudeM(t)), bsdfs.bsdf, bsdfs.deltaLight,
           frame, wo};
  if (rdb_.materials[mi].hasReflectionFog()) {
    v.fogDistanceM = rdb_.materials[mi].reflectionFogDistanceM;
    v.fogBsdf = &fogBsdfs_[mi];
  }
  return v;
}

template <class S>
Rgb Integrator::litPatchLight(const Vertex& v, uint32_t cell, uint32_t depth, S& sampler, uint64_t& rays,
                              Rgb& sunPart) const {
  sampler.startGroup(kPatchGroupBase + 2 * depth);
  const vec2 u = sampler.next2D();
  const LitPatches::Pick pick = litPatches_->sample(cell, u.x);
  const uint32_t t = pick.triangle;
  const float areaM2 = scene_.triangleAreaM2(t);
  if (!(areaM2 > 0.0f)) return Rgb(0.0f);
  const LitPatches::PointPick point = litPatches_->samplePoint(pick, vec2(pick.uRemapped, u.y));
  const vec3 b(1.0f - point.barycentric.x - point.barycentric.y, point.barycentric.x, point.barycentric.y);
  const vec3& p0 = rdb_.positionsM[rdb_.indices[3 * size_t{t}]];
  const vec3& p1 = rdb_.positionsM[rdb_.indices[3 * size_t{t} + 1]];
  const vec3& p2 = rdb_.positionsM[rdb_.indices[3 * size_t{t} + 2]];
  const vec3 y = b.x * p0 + b.y * p1 + b.z * p2;
  const vec3 toPatch = y - v.p;
  const float distM = glm::length(toPatch);
  if (!(distM > 0.0f)) return Rgb(0.0f);
  const vec3 d = toPatch / distM;
  const vec3& ng = scene_.triangleNormal(t);
  const float absCosPatch = std::abs(glm::dot(ng, d));
  Rgb fCos;
  float pdfBsdf;
  if (!(absCosPatch > 0.0f) || !response(v, v.bsdf, d, fCos, pdfBsdf, distM)) return Rgb(0.0f);
  const float pdf = pick.pmf * point.densityFactor / areaM2 * distM * distM / absCosPatch;
  if (!(pdf > 0.0f) || !std::isfinite(pdf)) return Rgb(0.0f);
  // y as the next vertex of the path, and the sun's and sky's light that a path reaching it samples there.
  std::optional<Bsdf> pointBsdf, pointDeltaLight;
  const TrianglePoint at{t, point.barycentric};
  const std::optional<Vertex> patch = vertexAt(y, at, ng, d, pointBsdf, pointDeltaLight);
  if (!patch || patch->bsdf->isBlack()) return Rgb(0.0f);
  const bool lightSampling = patch->bsdf->hasNonDelta();
  if (!lightSampling && !patch->deltaLightBsdf->hasNonDelta()) return Rgb(0.0f);
  Rgb sun(0.0f);
  const Rgb light = directLight(*patch, lightSampling && settings_.litPatchSky, kPatchGroupBase + 2 * depth + 1,
                                vec2(0.0f), 0.0f, sampler, rays, &sun, nullptr, true);
  if (!(maxComponent(light) > 0.0f)) return Rgb(0.0f);
  // Both ends moved off their surfaces, the patch's towards v.
  const vec3 origin = offsetRayOrigin(v.p, glm::dot(v.ng, d) > 0.0f ? v.ng : -v.ng, v.magnitudeM);
  const vec3 target = offsetRayOrigin(y, patch->ng, patch->magnitudeM);
  const vec3 toTarget = target - origin;
  const float targetDistM = glm::length(toTarget);
  if (!(targetDistM > 0.0f)) return Rgb(0.0f);
  const Rgb seen = visibility(origin, toTarget / targetDistM, targetDistM, rays);
  const Rgb weight = fCos * (patchWeight(pdf, pdfBsdf) / pdf) * seen;
  sunPart = weight * sun;
  return weight * light;
}

float Integrator::directlyLitRadiance(const Hit& hit, const vec3& d, uint64_t seed) const {
  std::optional<Bsdf> point, pointDeltaLight;
  const std::optional<Vertex> v =
      vertexAt(hitPoint(hit), {hit.triangle, hit.barycentric}, hit.geometricNormal, d, point, pointDeltaLight);
  if (!v || v->bsdf->isBlack()) return 0.0f;
  const bool lightSampling = v->bsdf->hasNonDelta();
  if (!lightSampling && !v->deltaLightBsdf->hasNonDelta()) return 0.0f;
  SobolSampler sampler(seed);
  sampler.startSample(0);
  uint64_t rays = 0;
  return luminance(directLight(*v, lightSampling && settings_.litPatchSky, 0, vec2(0.0f), 0.0f, sampler, rays,
                               nullptr, nullptr, true));
}

float Integrator::faceRadiance(uint32_t t, bool front) const {
  const vec3& ng = scene_.triangleNormal(t);
  const vec3 d = front ? -ng : ng;  // seen along the face's normal
  const uint64_t seed = detail::mix64(~(2 * uint64_t{t} + (front ? 0 : 1)));
  double sum = 0.0;
  for (uint32_t j = 0; j < kFaceRadianceSamples; ++j) {
    SobolSampler sampler(seed);
    sampler.startSample(j);
    sampler.startGroup(0);
    const vec3 b = sampleUniformTriangle(sampler.next2D());
    Hit hit;
    hit.triangle = t;
    hit.barycentric = vec2(b.y, b.z);
    hit.geometricNormal = ng;
    sum += directlyLitRadiance(hit, d, detail::mix64(seed + j + 1));
  }
  return float(sum / kFaceRadianceSamples);
}

void Integrator::buildLitPatches() {
  // Training points: every vertex on the side of its normal (turned to its triangles' front) and, for
  // double-sided materials, on the other.
  std::vector<LitPatches::TrainingPoint> points;
  std::vector<uint8_t> seen(2 * rdb_.positionsM.size(), 0);
  for (uint32_t t = 0; t < rdb_.triangleCount(); ++t) {
    if (!(scene_.triangleAreaM2(t) > 0.0f)) continue;
    const vec3& ng = scene_.triangleNormal(t);
    const bool doubleSided = rdb_.materials[rdb_.triangleMaterial[t]].doubleSided;
    for (uint32_t c = 0; c < 3; ++c) {
      const uint32_t vi = rdb_.indices[3 * size_t{t} + c];
      vec3 n = rdb_.normals[vi];
      if (!(glm::dot(n, ng) > 0.0f)) n = ng;
      for (uint32_t side = 0; side < (doubleSided ? 2u : 1u); ++side) {
        if (seen[2 * size_t{vi} + side]) continue;
        seen[2 * size_t{vi} + side] = 1;
        points.push_back({rdb_.positionsM[vi], side == 0 ? n : -n, scene_.triangleMagnitudeM(t)});
      }
    }
  }
  // Points inside the triangles that are large for the cells: a low-poly room's floor of two triangles has
  // vertices only in its corners, and the cells over its middle would otherwise learn nothing.
  const float spacingM = LitPatches::cellSizeM(points, rdb_.indices, rdb_.positionsM) / kTrainingPointsPerCellSide;
  for (uint32_t t = 0; settings_.litPatchInteriorTraining && t < rdb_.triangleCount(); ++t) {
    if (!(scene_.triangleAreaM2(t) > 0.0f)) continue;
    const uint32_t* tri = &rdb_.indices[3 * size_t{t}];
    const vec3 &p0 = rdb_.positionsM[tri[0]], &p1 = rdb_.positionsM[tri[1]], &p2 = rdb_.positionsM[tri[2]];
    const float longestM = std::max({glm::length(p1 - p0), glm::length(p2 - p1), glm::length(p0 - p2)});
    if (!(longestM > spacingM)) continue;
    const uint32_t n = static_cast<uint32_t>(std::min(std::ceil(longestM / spacingM), float(kMaxTrainingSplit)));
    const vec3& ng = scene_.triangleNormal(t);
    const bool doubleSided = rdb_.materials[rdb_.triangleMaterial[t]].doubleSided;
    const vec3 &n0 = rdb_.normals[tri[0]], &n1 = rdb_.normals[tri[1]], &n2 = rdb_.normals[tri[2]];
    // Sub-triangle centroids at barycentric coordinates (b1, b2) of p1 and p2: n(n+1)/2 pointing one way and
    // n(n−1)/2 the other.
    auto add = [&](float b1, float b2) {
      const float b0 = 1.0f - b1 - b2;
      const vec3 p = b0 * p0 + b1 * p1 + b2 * p2;
      vec3 nrm = b0 * n0 + b1 * n1 + b2 * n2;
      nrm = glm::dot(nrm, ng) > 0.0f ? glm::normalize(nrm) : ng;
      if (!std::isfinite(nrm.x)) nrm = ng;
      points.push_back({p, nrm, scene_.triangleMagnitudeM(t)});
      if (doubleSided) points.push_back({p, -nrm, scene_.triangleMagnitudeM(t)});
    };
    const float inv = 1.0f / float(n);
    for (uint32_t i = 0; i < n; ++i) {
      for (uint32_t j = 0; i + j < n; ++j) {
        add((float(i) + 1.0f / 3.0f) * inv, (float(j) + 1.0f / 3.0f) * inv);
        if (i + j + 1 < n) add((float(i) + 2.0f / 3.0f) * inv, (float(j) + 2.0f / 3.0f) * inv);
      }
    }
  }
  std::vector<uint8_t> passesStraight(rdb_.triangleCount(), 0);
  for (uint32_t t = 0; t < rdb_.triangleCount(); ++t) {
    passesStraight[t] = frontBsdfs_[rdb_.triangleMaterial[t]].hasClearTransmission() ? 1 : 0;
  }
  auto patches = std::make_unique<const LitPatches>(
      scene_, points, passesStraight, rdb_.indices, rdb_.positionsM,
      [this](const Hit& hit, const vec3& d, uint64_t seed) { return directlyLitRadiance(hit, d, seed); },
      [this](uint32_t t, bool front) { return faceRadiance(t, front); }, settings_.litPatchMaps);

  if (!patches->empty()) litPatches_ = std::move(patches);
}

template <class S>
Rgb Integrator::sampleIrradiance(const vec3& p, const vec3& n, S& sampler, uint64_t& rays,
                                 float surfaceMagnitudeM, Rgb* sunDirectLux, Rgb* sunLux) const {
  Rgb sum(0.0f);
  if (sunDirectLux) *sunDirectLux = Rgb(0.0f);
  if (sunLux) *sunLux = Rgb(0.0f);
  // Path throughput: Π f |cos θ| / pdf over the vertices passed (π at the sensor, whose integrand is L cos
  // θ), over the Russian-roulette survival probabilities.
  Rgb beta(1.0f);
  Vertex v{p, n, n, std::max(maxAbs(p), surfaceMagnitudeM), nullptr, nullptr, onb(n), vec3(0.0f)};
  // A hit's scattering functions when its material varies over the surface (bsdfsAt).
  std::optional<Bsdf> pointBsdf, pointDeltaLightBsdf;
  // Light that the next ray finds is MIS-weighted against light sampling at the last non-delta vertex, with
  // the density pdfLast of its continuation and the distance travelledM from it (straight through clear
  // panes included), unless the last scattering was a mirror (`specular`): light sampling cannot find that.
  bool specular = false;
  float pdfLast = 0.0f;
  float travelledM = 0.0f;
  vec3 misOrigin = p;  // that vertex's position, for the sky portals' density (skyLightPdf)
  float misPortalFraction = kSensorPortalFraction;  // and its share of sky samples through the portals
  // Reflections so far (straight passages through clear panes are none); a vertex's light-sampled light has
  // been reflected reflections + 1 times.
  uint32_t reflections = 0;
  const uint32_t maxReflections = std::min(settings_.maxBounces, kPathLengthGuard);
  // Whether v may only pass light straight through (it would be a reflection too many).
  bool straightOnly = false;
  // Next-event estimation to lit patches: the region of the last non-delta vertex when it sampled patches
  // (LitPatches::kNoCell otherwise, and after a mirror), and the MIS weight of v's sun and sky light against
  // that vertex's patch sample of v.
  uint32_t patchCellLast = LitPatches::kNoCell;
  // v's triangle and |cos θ| of the ray that reached it, for that vertex's density of a patch sample of v.
  uint32_t triangleOfV = 0;
  vec2 barycentricOfV(0.0f);
  float absCosOfV = 0.0f;
  // With rouletteAfterLight, v's survival probability (1: none) and its roulette number, applied once v's
  // lights are sampled.
  float pendingSurvival = 1.0f;
  float pendingRoulette = 0.0f;
  // Reflection fog at v for its continuation (v.fogBsdf): the per-channel share ρ of the sample's weight that
  // its reflection lobe carries, and its scalar share s (0: no fog for this continuation).
  Rgb fogShare(0.0f);
  float fogShareScalar = 0.0f;
  for (uint32_t depth = 0; depth <= kPathLengthGuard; ++depth) {
    // Only the dimensions this vertex uses (each is a function of its own index alone, so skipping one
    // changes no other).
    // All lights where v has a non-delta lobe; the sun and punctual lights also where only its regularised
    // twin has one (a mirror without caustics).
    const bool lightSampling = !straightOnly && (v.bsdf == nullptr || v.bsdf->hasNonDelta());
    v.portalShare = 0.0f;
    if (settings_.portalContinuation && !portalPlanes_.empty() && !straightOnly &&
        (v.bsdf == nullptr || v.bsdf->isLambertian())) {
      v.portalShare = portalContinuationShare(v.p, v.portalWeight);
    }
    const bool deltaLightSampling = lightSampling || (!straightOnly && v.deltaLightBsdf->hasNonDelta());
    const bool roulette = depth + 1 >= kFirstRouletteVertex;
    const bool lobeChoice = !straightOnly && v.bsdf != nullptr && !v.bsdf->isLambertian();
    const bool punctualChoice = deltaLightSampling && positionalDistribution_;
    float uRoulette = 0.0f;
    float uLobe = 0.0f;
    float uPunctual = 0.0f;
    if (roulette || lobeChoice || punctualChoice) {
      sampler.startGroup(kGroupsPerVertex * depth + 2);
      if (roulette)
        uRoulette = sampler.next1D();
      else
        sampler.skip(1);
      if (lobeChoice)
        uLobe = sampler.next1D();
      else
        sampler.skip(1);
      if (punctualChoice) uPunctual = sampler.next1D();
    }
    vec2 uContinue(0.0f);
    vec2 uEmitter(0.0f);
    if (!straightOnly || (lightSampling && emitterDistribution_)) {
      sampler.startGroup(kGroupsPerVertex * depth + 1);
      uContinue = sampler.next2D();
      if (lightSampling && emitterDistribution_) uEmitter = sampler.next2D();
    }

    if (deltaLightSampling) {
      // At the sensor (depth 0, β = 1) the sun's sample is the sun-direct part.
      Rgb sunPart(0.0f);
      Rgb sunSkyPart(0.0f);
      const Rgb light = directLight(v, lightSampling, kGroupsPerVertex * depth, uEmitter, uPunctual, sampler,
                                    rays, &sunPart, &sunSkyPart);
      // The light that the patch samples also gather, and its weight against the last non-delta vertex's
      // patch sample of v (evaluated where that light is not 0: the weight multiplies it alone).
      const Rgb& patchLight = settings_.litPatchSky ? sunSkyPart : sunPart;
      float sunSkyWeight = 1.0f;
      if (patchCellLast != LitPatches::kNoCell && !specular && maxComponent(patchLight) > 0.0f) {
        const float density = litPatches_->density(patchCellLast, triangleOfV, barycentricOfV);
        if (density > 0.0f) {
          const float pdfPatch =
              density / scene_.triangleAreaM2(triangleOfV) * travelledM * travelledM / absCosOfV;
          if (std::isfinite(pdfPatch)) sunSkyWeight = 1.0f - patchWeight(pdfPatch, pdfLast);
        }
      }
      sum += beta * (light - (1.0f - sunSkyWeight) * patchLight);
      if (depth == 0 && sunDirectLux) *sunDirectLux = sunPart;
      if (sunLux) *sunLux += beta * sunSkyWeight * sunPart;
    }

    // Next-event estimation to lit patches, where v samples lights, has a region with a distribution, and a
    // path continued from it could still sample lights at its next vertex.
    uint32_t patchCell = LitPatches::kNoCell;
    if (litPatches_ && lightSampling && reflections + (v.bsdf ? 1u : 0u) < maxReflections &&
        depth < kPathLengthGuard) {
      patchCell = litPatches_->cellOf(v.p, v.n);
      if (patchCell != LitPatches::kNoCell) {
        Rgb sunPart(0.0f);
        const Rgb patch = litPatchLight(v, patchCell, depth, sampler, rays, sunPart);
        sum += beta * patch;
        if (sunLux) *sunLux += beta * sunPart;
      }
    }
    if (pendingSurvival < 1.0f) {
      if (pendingRoulette >= pendingSurvival) break;
      beta /= pendingSurvival;
      pendingSurvival = 1.0f;
    }

    // The continuation.
    vec3 d;
    if (v.bsdf == nullptr) {
      // At the sensor, whose integrand is L cos θ: cos θ / pdf (π for the cosine alone).
      float cosTheta = 0.0f;
      if (!sampleContinuation(v, uContinue, d, cosTheta, pdfLast)) break;
      beta *= cosTheta / pdfLast;
      travelledM = 0.0f;
      misOrigin = v.p;
      misPortalFraction = kSensorPortalFraction;
      patchCellLast = patchCell;
    } else if (straightOnly) {
      d = v.frame.toWorld(-v.woLocal);
      beta *= v.bsdf->straightTransmittance(v.woLocal.z);
    } else if (v.bsdf->isLambertian()) {
      // f |cos θ| / pdf = (ρ/π) cos θ / pdf (ρ for the cosine alone).
      float cosTheta = 0.0f;
      if (!sampleContinuation(v, uContinue, d, cosTheta, pdfLast)) break;
      if (!(glm::dot(d, v.ng) > 0.0f)) break;  // below the geometric surface: no light comes from there
      beta *= v.bsdf->lambertAlbedo() * (cosTheta / (kPiF * pdfLast));
      ++reflections;
      specular = false;
      travelledM = 0.0f;
      misOrigin = v.p;
      misPortalFraction = kPortalFraction;
      patchCellLast = patchCell;
    } else {
      Bsdf::Sample s;
      if (!v.bsdf->sample(v.woLocal, uLobe, uContinue, s)) break;
      d = glm::normalize(v.frame.toWorld(s.wi));
      // Where the shading and geometric surfaces disagree on the side, no light comes from there.
      if (s.lobe != Bsdf::Lobe::kStraight && (glm::dot(d, v.ng) > 0.0f) != (s.wi.z > 0.0f)) break;
      beta *= s.weight;
      fogShareScalar = 0.0f;
      if (v.fogBsdf && s.lobe == Bsdf::Lobe::kMirror) {
        fogShare = Rgb(1.0f);
        fogShareScalar = 1.0f;
      } else if (v.fogBsdf && s.lobe == Bsdf::Lobe::kNonDelta) {
        const Rgb f = v.bsdf->eval(v.woLocal, s.wi);
        const Rgb fReflection = v.bsdf->evalReflection(v.woLocal, s.wi);
        for (int c = 0; c < 3; ++c) fogShare[c] = f[c] > 0.0f ? std::clamp(fReflection[c] / f[c], 0.0f, 1.0f) : 0.0f;
        const float weightSum = s.weight.r + s.weight.g + s.weight.b;
        fogShareScalar = weightSum > 0.0f ? glm::dot(s.weight, fogShare) / weightSum : 0.0f;
      }
      if (s.lobe != Bsdf::Lobe::kStraight) {
        ++reflections;
        specular = s.lobe == Bsdf::Lobe::kMirror;
        pdfLast = s.pdf;
        travelledM = 0.0f;
        misOrigin = v.p;
        misPortalFraction = kPortalFraction;
        patchCellLast = specular ? LitPatches::kNoCell : patchCell;
      }
    }
    if (!(maxComponent(beta) > 0.0f)) break;

    ++rays;
    const std::optional<Hit> hit =
        scene_.intersect(offsetRayOrigin(v.p, glm::dot(v.ng, d) > 0.0f ? v.ng : -v.ng, v.magnitudeM), d,
                         std::numeric_limits<float>::infinity());
    if (fogShareScalar > 0.0f) {
      // Reflection fog: the reflected light ρ W L(y) seen at distance d becomes (1 − t) ρ W L(y) + t ρ W
      // L_fog, L_fog = fogColor E(x) / π, the radiance of a Lambertian surface of albedo fogColor at v. One of
      // the two is followed: the fog with probability P = t s, weight ρ W / s, in the form of a virtual
      // vertex at v with that Lambertian Bsdf (its light sampling and continuation estimate E / π times the
      // albedo); the ray's hit otherwise, weight (W − t ρ W) / (1 − P). Both expectations are the terms
      // above: unbiased. Light sampling at v faded the reflection lobe alike (response), so the MIS of v's
      // light sampling against the hit's emission estimates one integrand.
      const float t = hit ? fogFraction(hit->distanceM, v.fogDistanceM) : 1.0f;
      const float share = fogShareScalar;
      const float pFog = std::min(t * share, 1.0f);
      fogShareScalar = 0.0f;
      sampler.startGroup(kFogGroupBase + depth);
      if (sampler.next1D() < pFog) {
        beta *= fogShare / share;
        if (v.fogBsdf->isBlack() || !(maxComponent(beta) > 0.0f)) break;
        // The virtual vertex scatters in place of v's reflection: its continuation is that reflection.
        --reflections;
        v.bsdf = v.fogBsdf;
        v.deltaLightBsdf = v.fogBsdf;
        v.fogBsdf = nullptr;
        v.fogDistanceM = std::numeric_limits<float>::infinity();
        patchCellLast = LitPatches::kNoCell;
        continue;
      }
      beta *= (Rgb(1.0f) - t * fogShare) / (1.0f - pFog);
    }
    if (!hit) {
      if (skyDistribution_ && d.y >= 0.0f) {
        const uint32_t cell = skyCell(d);
        sum += beta * rdb_.sky.radianceCdM2[cell] *
               (specular ? 1.0f
                         : powerHeuristic(pdfLast, skyLightPdf(misOrigin, d, cell, portalWeight(misOrigin), misPortalFraction)));
      }
      // Within the sun's cone: 1 − cos = |d − s|² / 2, without cancellation.
      if (specular && settings_.caustics && sunOneMinusCos_ > 0.0f) {
        const vec3 offAxis = d - rdb_.sun.directionWorld;
        if (0.5f * glm::dot(offAxis, offAxis) <= sunOneMinusCos_) {
          sum += beta * sunRadianceCdM2_;
          if (sunLux) *sunLux += beta * sunRadianceCdM2_;
        }
      }
      break;
    }
    travelledM += hit->distanceM;
    const float cosLight = -glm::dot(hit->geometricNormal, d);
    const bool front = cosLight > 0.0f;
    const uint32_t t = hit->triangle;
    const uint32_t mi = rdb_.triangleMaterial[t];
    const rdb::TraceMaterial& m = rdb_.materials[mi];
    const TrianglePoint at{t, hit->barycentric};
    if (emitterDistribution_ && emitterPmfOfTriangle_[t] > 0.0f && (front || m.doubleSided)) {
      sum += beta * emissionAt(rdb_, m, at) *
             (specular ? 1.0f : powerHeuristic(pdfLast, emitterPdf(t, travelledM, std::abs(cosLight))));
    }
    straightOnly = reflections >= maxReflections;
    const std::optional<Vertex> next =
        vertexAt(hitPoint(*hit), at, hit->geometricNormal, d, pointBsdf, pointDeltaLightBsdf);
    if (!next || next->bsdf->isBlack() || (straightOnly && !next->bsdf->passesStraight())) break;
    v = *next;
    const Bsdf& bsdf = *v.bsdf;
    const vec3& wo = v.woLocal;
    triangleOfV = t;
    barycentricOfV = hit->barycentric;
    absCosOfV = std::abs(cosLight);

    // Russian roulette from vertex kFirstRouletteVertex on, a weight window (IntegratorSettings::
    // rouletteWindow) on the throughput relative to the sensor's (β / π) times the albedo that the path
    // carries past this vertex: here, or with IntegratorSettings::rouletteAfterLight once v's lights are
    // sampled.
    if (roulette) {
      const float q =
          std::min(1.0f, maxComponent(beta * bsdf.albedo(wo.z)) / (kPiF * settings_.rouletteWindow));
      if (settings_.rouletteAfterLight) {
        pendingSurvival = q;
        pendingRoulette = uRoulette;
      } else {
        if (uRoulette >= q) break;
        beta /= q;
      }
    }
  }
  return sum;
}

template Rgb Integrator::sampleIrradiance(const vec3&, const vec3&, SobolSampler&, uint64_t&, float, Rgb*,
                                          Rgb*) const;
template Rgb Integrator::sampleIrradiance(const vec3&, const vec3&, RandomSampler&, uint64_t&, float, Rgb*,
                                          Rgb*) const;

namespace {

// estimateIrradiance's sensors.
class SensorSource final : public SampleSourceOf<SensorSource> {
  friend SampleSourceOf<SensorSource>;

 public:
  SensorSource(const Integrator& integrator, std::span<const vec3> points, std::span<const vec3> normals,
               std::span<const float> magnitudesM)
      : integrator_(integrator), points_(points), normals_(normals), magnitudesM_(magnitudesM) {}

  size_t pointCount() const override { return points_.size(); }

 private:
  template <class S>
  Rgb sampleAt(size_t i, S& sampler, uint64_t& rays) const {
    return integrator_.sampleIrradiance(points_[i], normals_[i], sampler, rays,
                                        magnitudesM_.empty() ? 0.0f : magnitudesM_[i]);
  }

  const Integrator& integrator_;
  std::span<const vec3> points_;
  std::span<const vec3> normals_;
  std::span<const float> magnitudesM_;
};

}  // namespace

EstimateResult estimateIrradiance(const Integrator& integrator, std::span<const vec3> points,
                                  std::span<const vec3> normals, const EstimateSettings& settings,
                                  std::span<const float> surfaceMagnitudesM) {
  if (points.size() != normals.size() ||
      (!surfaceMagnitudesM.empty() && surfaceMagnitudesM.size() != points.size())) {
    throw std::invalid_argument("estimateIrradiance: " + std::to_string(points.size()) + " points but " +
                                std::to_string(normals.size()) + " normals and " +
                                std::to_string(surfaceMagnitudesM.size()) + " surface magnitudes");
  }
  return estimateProgressively(SensorSource(integrator, points, normals, surfaceMagnitudesM), settings);
}

}  // namespace fly::raytracer
