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

std::shared_ptr<const BrdfTable> TabulatedLobe::regularised(const BrdfTable& table, float radiusRad) {
  constexpr int kRows = BrdfTable::kThetaHalfRes;
  // Each θh row's angle and the solid angle of the band it stands for (between the midpoints to its
  // neighbours in the table's coordinate u = √(θh / (π/2))).
  std::array<double, kRows> thetaH{}, band{};
  for (int i = 0; i < kRows; ++i) {
    thetaH[size_t(i)] = double(BrdfTable::sampleAngles(i, 0, 0).thetaHalfRad);
    const double lo = std::max(0.0, (i - 0.5) / kRows), hi = std::min(1.0, (i + 0.5) / kRows);
    band[size_t(i)] = std::cos(lo * lo * 0.5 * kPi) - std::cos(hi * hi * 0.5 * kPi);
  }
  // kernel[i][n]: the share of the cap of radius r around a half vector at θh_i that row n's band covers,
  // band_n · Δφ(θ_i, θ_n) / 2π, with Δφ the azimuth range of the ring at θ_n inside the cap (spherical law of
  // cosines: cos d = cos θ_i cos θ_n + sin θ_i sin θ_n cos Δφ/2 ≤ cos r). It is symmetric once weighted by
  // band_i, so spreading keeps a column's integral over half vectors as well as a constant.
  const double cosR = std::cos(double(radiusRad));
  std::vector<double> kernel(size_t(kRows) * kRows, 0.0);
  for (int i = 0; i < kRows; ++i) {
    for (int n = 0; n < kRows; ++n) {
      const double a = thetaH[size_t(i)], b = thetaH[size_t(n)];
      const double denominator = std::sin(a) * std::sin(b);
      double coverage;  // Δφ / 2π
      if (denominator <= 0.0) {
        coverage = std::abs(a - b) <= double(radiusRad) ? 1.0 : 0.0;
      } else {
        const double c = (cosR - std::cos(a) * std::cos(b)) / denominator;
        coverage = c <= -1.0 ? 1.0 : (c >= 1.0 ? 0.0 : std::acos(c) / kPi);
      }
      kernel[size_t(i) * kRows + size_t(n)] = band[size_t(n)] * coverage;
    }
  }
  const std::vector<uint8_t>& valid = BrdfTable::validSamples();
  std::vector<Rgb> samples(BrdfTable::kSamples);
  for (int j = 0; j < BrdfTable::kThetaDiffRes; ++j) {
    for (int k = 0; k < BrdfTable::kPhiDiffRes; ++k) {
      for (int i = 0; i < kRows; ++i) {
        const size_t index = BrdfTable::sampleIndex(i, j, k);
        samples[index] = table.sample(i, j, k);
        if (!valid[index]) continue;
        // The cap's mean over the measured rows (the others hold no measurement).
        dvec3 sum(0.0);
        double weights = 0.0;
        for (int n = 0; n < kRows; ++n) {
          const double w = kernel[size_t(i) * kRows + size_t(n)];
          if (w > 0.0 && valid[BrdfTable::sampleIndex(n, j, k)]) {
            sum += w * dvec3(table.sample(n, j, k));
            weights += w;
          }
        }
        if (weights > 0.0) samples[index] = Rgb(sum / weights);
      }
    }
  }
  return std::make_shared<const BrdfTable>(std::move(samples));
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
