#include "rdb/raster_measured_brdf.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "sdb/material.h"

namespace fly::rdb {
namespace {

// ρ(θo) per channel by the midpoint rule over the half vector h = (θh, φh) with θh = u² · π/2 (the MERL
// table's own warp, dense near the mirror direction where a glossy lobe lives): ωi = 2(ωo·h)h − ωo and
// dωi = 4 (ωo·h) dωh (Walter et al. 2007, eq. 14), dωh = sin θh · π u du dφh.
template <class Eval>
Rgb directionalAlbedo(const Eval& evalPerSr, float cosThetaOut) {
  constexpr int kU = 96, kPhi = 96;
  const float c = std::clamp(cosThetaOut, 1e-4f, 1.0f);
  const vec3 wo(std::sqrt(1.0f - c * c), 0.0f, c);
  dvec3 sum(0.0);
  for (int a = 0; a < kU; ++a) {
    const double u = (a + 0.5) / kU;
    const double thetaH = u * u * kPi / 2;
    const double weightU = std::sin(thetaH) * kPi * u / kU;
    for (int b = 0; b < kPhi; ++b) {
      const double phi = 2.0 * kPi * (b + 0.5) / kPhi;
      const vec3 h(float(std::sin(thetaH) * std::cos(phi)), float(std::sin(thetaH) * std::sin(phi)),
                   float(std::cos(thetaH)));
      const float woDotH = glm::dot(wo, h);
      if (!(woDotH > 0.0f)) continue;
      const vec3 wi = 2.0f * woDotH * h - wo;
      if (!(wi.z > 0.0f)) continue;
      sum += dvec3(evalPerSr(wi, wo)) * (double(wi.z) * 4.0 * woDotH * weightU * 2.0 * kPi / kPhi);
    }
  }
  return Rgb(sum);
}

}  // namespace

RasterMeasuredBrdf lowerMeasuredBrdf(const sdb::Material& m, uint32_t sdbMaterialId) {
  if (!m.isMeasured()) throw std::invalid_argument("lowerMeasuredBrdf: the material has no measured BRDF");
  RasterMeasuredBrdf r;
  r.sdbMaterialId = sdbMaterialId;
  r.albedo.resize(kRasterAlbedoSteps);
  if (m.measuredBrdf) {
    const sdb::MeasuredBrdf& t = *m.measuredBrdf;
    r.kind = RasterBrdfKind::kTable;
    const std::vector<uint8_t>& valid = sdb::MeasuredBrdf::validSamples();
    r.tableRgba.resize(4 * sdb::MeasuredBrdf::kSamples);
    for (int i = 0; i < sdb::MeasuredBrdf::kThetaHalfRes; ++i) {
      for (int j = 0; j < sdb::MeasuredBrdf::kThetaDiffRes; ++j) {
        for (int k = 0; k < sdb::MeasuredBrdf::kPhiDiffRes; ++k) {
          const size_t s = sdb::MeasuredBrdf::sampleIndex(i, j, k);
          const Rgb& v = t.sample(i, j, k);
          r.tableRgba[4 * s + 0] = v.r;
          r.tableRgba[4 * s + 1] = v.g;
          r.tableRgba[4 * s + 2] = v.b;
          r.tableRgba[4 * s + 3] = valid[s] ? 1.0f : 0.0f;
        }
      }
    }
    for (uint32_t k = 0; k < kRasterAlbedoSteps; ++k) {
      r.albedo[k] = directionalAlbedo([&](const vec3& wi, const vec3& wo) { return t.evalPerSr(wi, wo); },
                                      (float(k) + 0.5f) / float(kRasterAlbedoSteps));
    }
    return r;
  }
  const sdb::CarPaintBrdf& p = *m.carPaint;
  r.kind = RasterBrdfKind::kCarPaint;
  r.carPaint.baseAlbedo = p.baseAlbedo;
  for (size_t k = 0; k < 3; ++k) {
    r.carPaint.lobeF0[k] = p.lobes[k].f0;
    r.carPaint.lobeAlpha[k] = p.lobes[k].alpha;
  }
  r.carPaint.coatIor = p.coatIor;
  r.carPaint.coatAlpha = p.coatAlpha;
  r.carPaint.internalDiffuseReflectance = sdb::internalDiffuseReflectance(p.coatIor);
  for (uint32_t k = 0; k < kRasterAlbedoSteps; ++k) {
    r.albedo[k] = directionalAlbedo([&](const vec3& wi, const vec3& wo) { return p.evalPerSr(wi, wo); },
                                    (float(k) + 0.5f) / float(kRasterAlbedoSteps));
  }
  return r;
}

}  // namespace fly::rdb
