#include "raytracer/tabulated_lobe.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "raytracer/warp.h"

namespace fly::raytracer {
namespace {

constexpr float kHalfPiF = 0.5f * kPiF;

// The solid angle of the cells of θh row `row` (each kPhiHalfBins-th of half a turn).
float cellSolidAngle(const std::array<float, TabulatedLobe::kThetaHalfBins + 1>& oneMinusCosEdge, int row) {
  return (oneMinusCosEdge[size_t(row) + 1] - oneMinusCosEdge[size_t(row)]) * (kPiF / TabulatedLobe::kPhiHalfBins);
}

// The half vector at 1 − cos θh = w and azimuth φ: sin θh = √(w (2 − w)) without cancellation near the normal.
vec3 halfVector(float oneMinusCos, float phi) {
  const float sinH = std::sqrt(std::max(0.0f, oneMinusCos * (2.0f - oneMinusCos)));
  return vec3(sinH * std::cos(phi), sinH * std::sin(phi), 1.0f - oneMinusCos);
}

float mean(const Rgb& c) { return (c.r + c.g + c.b) / 3.0f; }

}  // namespace

TabulatedLobe::TabulatedLobe(std::shared_ptr<const BrdfTable> table, float scale)
    : table_(std::move(table)), scale_(scale) {
  for (int i = 0; i <= kThetaHalfBins; ++i) {
    const float u = float(i) / kThetaHalfBins;
    oneMinusCosThetaHalfEdge_[size_t(i)] = oneMinusCos(u * u * kHalfPiF);
  }
  oneMinusCosThetaHalfEdge_[kThetaHalfBins] = 1.0f;
  halfVectors_.reserve(kThetaOBins);
  albedo_.reserve(kThetaOBins);
  std::vector<float> cells(size_t(kThetaHalfBins) * kPhiHalfBins);
  for (int bin = 0; bin < kThetaOBins; ++bin) {
    const float thetaO = (float(bin) + 0.5f) / kThetaOBins * kHalfPiF;
    const vec3 wo(std::sin(thetaO), 0.0f, std::cos(thetaO));
    dvec3 albedo(0.0);
    for (int row = 0; row < kThetaHalfBins; ++row) {
      const float omega = cellSolidAngle(oneMinusCosThetaHalfEdge_, row);
      for (int col = 0; col < kPhiHalfBins; ++col) {
        // g at 2 × 2 points placed evenly in solid angle (cos θh and φ) within the cell.
        Rgb g(0.0f);
        for (int s = 0; s < 4; ++s) {
          const float fy = (float(s >> 1) + 0.5f) * 0.5f;
          const float fx = (float(s & 1) + 0.5f) * 0.5f;
          const vec3 h = halfVector(
              glm::mix(oneMinusCosThetaHalfEdge_[size_t(row)], oneMinusCosThetaHalfEdge_[size_t(row) + 1], fy),
              (float(col) + fx) * (kPiF / kPhiHalfBins));
          const float woDotH = glm::dot(wo, h);
          if (!(woDotH > 0.0f)) continue;
          const vec3 wi = 2.0f * woDotH * h - wo;
          if (!(wi.z > 0.0f)) continue;
          g += eval(wo, wi) * (wi.z * 4.0f * woDotH);
        }
        g *= 0.25f;
        // The cell's integral of g; its mirror cell (φ < 0) holds as much again.
        albedo += 2.0 * dvec3(g) * double(omega);
        cells[size_t(row) * kPhiHalfBins + size_t(col)] = mean(g) * omega;
      }
    }
    halfVectors_.emplace_back(cells, uint32_t(kPhiHalfBins), uint32_t(kThetaHalfBins));
    albedo_.push_back(Rgb(albedo));
  }
}

int TabulatedLobe::thetaOBin(float cosO) {
  const float thetaO = std::acos(std::clamp(cosO, 0.0f, 1.0f));
  return std::clamp(int(thetaO / kHalfPiF * kThetaOBins), 0, kThetaOBins - 1);
}

float TabulatedLobe::halfVectorPdf(int bin, const vec3& h, float phiO) const {
  const float thetaH = std::atan2(std::sqrt(h.x * h.x + h.y * h.y), h.z);
  const int row = std::clamp(int(std::sqrt(std::max(0.0f, thetaH / kHalfPiF)) * kThetaHalfBins), 0,
                             kThetaHalfBins - 1);
  // φh − φo folded into [0, π].
  const float phi = std::abs(std::remainder(std::atan2(h.y, h.x) - phiO, 2.0f * kPiF));
  const float x = std::clamp(phi / kPiF, 0.0f, 1.0f);
  const float cell = halfVectors_[size_t(bin)].pdf(vec2(x, (float(row) + 0.5f) / kThetaHalfBins)) /
                     float(kThetaHalfBins * kPhiHalfBins);
  return 0.5f * cell / cellSolidAngle(oneMinusCosThetaHalfEdge_, row);
}

float TabulatedLobe::pdf(const vec3& wo, const vec3& wi) const {
  if (!(wo.z > 0.0f) || !(wi.z > 0.0f)) return 0.0f;
  const vec3 h = glm::normalize(wo + wi);
  const float woDotH = glm::dot(wo, h);
  const float phiO = wo.x == 0.0f && wo.y == 0.0f ? 0.0f : std::atan2(wo.y, wo.x);
  const float table = woDotH > 0.0f ? halfVectorPdf(thetaOBin(wo.z), h, phiO) / (4.0f * woDotH) : 0.0f;
  return kCosineFraction * cosineHemispherePdf(wi.z) + (1.0f - kCosineFraction) * table;
}

bool TabulatedLobe::sample(const vec3& wo, float uChoice, const vec2& u, vec3& wi) const {
  if (!(wo.z > 0.0f)) return false;
  if (uChoice < kCosineFraction) {
    wi = sampleCosineHemisphere(u);
    return wi.z > 0.0f;
  }
  // The rest of uChoice picks the side of the plane of ωo and the normal.
  const float side = (uChoice - kCosineFraction) / (1.0f - kCosineFraction);
  const Distribution2D::Sample s = halfVectors_[size_t(thetaOBin(wo.z))].sample(u);
  const int row = int(s.cell / kPhiHalfBins);
  // Uniform in solid angle within the cell: cos θh linear across the row's fraction.
  const float fy = std::clamp(s.p.y * kThetaHalfBins - float(row), 0.0f, 1.0f);
  const float phiO = wo.x == 0.0f && wo.y == 0.0f ? 0.0f : std::atan2(wo.y, wo.x);
  const vec3 h = halfVector(
      glm::mix(oneMinusCosThetaHalfEdge_[size_t(row)], oneMinusCosThetaHalfEdge_[size_t(row) + 1], fy),
      phiO + (side < 0.5f ? 1.0f : -1.0f) * s.p.x * kPiF);
  const float woDotH = glm::dot(wo, h);
  if (!(woDotH > 0.0f)) return false;
  wi = glm::normalize(2.0f * woDotH * h - wo);
  return wi.z > 0.0f;
}

}  // namespace fly::raytracer
