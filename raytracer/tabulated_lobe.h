// A measured BRDF table (base/brdf_table.h) as a Bsdf lobe: evaluated by the table's trilinear interpolation,
// sampled by a tabulated density of half vectors mixed with cosine sampling.
//
// Sampling follows the factored, per-view tabulation of Lawrence, Rusinkiewicz & Ramamoorthi ("Efficient BRDF
// importance sampling using a factored representation", SIGGRAPH 2004) in the half-vector parametrisation
// they and Matusik et al. (2003) use: for each of kThetaOBins bins of the outgoing angle θo, a piecewise-
// constant 2D density over half vectors h, in cells of
//   θh: the table's own θh coordinate u = √(θh / (π/2)) in kThetaHalfBins equal steps (dense near the
//       highlight, as the table is, so that a sharp highlight falls in cells as narrow as its samples);
//   φh − φo: kPhiHalfBins equal steps over [0, π] (an isotropic BRDF is symmetric about the plane of ωo and
//       the normal, so the other half is its mirror image, chosen with probability 1/2),
// where each cell's probability is the integral over the cell of the target g(h) = f(ωo, ωi) cos θi · 4 (ωo·h)
// (the density ∝ f cos θi of ωi = reflect(ωo, h), times the Jacobian dωi/dωh = 4 ωo·h), estimated from 2 × 2
// points at the bin's central θo, and h is uniform in solid angle within its cell. So
//   p_table(ωi) = P(cell) / (2 Ω(cell)) / (4 ωo·h),
// with Ω(cell) the cell's solid angle. A fraction kCosineFraction of the draws are cosine-distributed instead
// (cos θi / π), which keeps the density positive wherever the 2 × 2 estimate of a cell is 0 but f is not (a
// cell that straddles the horizon, a feature narrower than a cell). The same sums give the directional
// albedo per θo bin (albedo()).
//
// Cost: one table (kThetaOBins · kThetaHalfBins · kPhiHalfBins cells, 2 × 2 evaluations each, 368 640 in all)
// is built once per measured file at the integrator's start (60–100 ms, docs/benchmarks.md); it holds 92 160
// cells, about 1.5 MB with their cumulative tables.
#pragma once

#include <array>
#include <memory>
#include <vector>

#include "base/brdf_table.h"
#include "raytracer/distribution.h"
#include "raytracer/measured_lobe.h"

namespace fly::raytracer {

class TabulatedLobe final : public MeasuredLobe {
 public:
  static constexpr int kThetaOBins = 32;      // equal steps of θo over [0, π/2]
  static constexpr int kThetaHalfBins = BrdfTable::kThetaHalfRes;  // of u = √(θh / (π/2)) over [0, 1]
  static constexpr int kPhiHalfBins = 32;     // of φh − φo over [0, π]
  static constexpr float kCosineFraction = 0.1f;

  // table: never null; scale multiplies it (TraceBrdfTable::scale).
  TabulatedLobe(std::shared_ptr<const BrdfTable> table, float scale);

  // The table with its highlights blurred for path regularisation (IntegratorSettings::caustics = false):
  // each (θd, φd) column, taken as a function of the half vector's angle θh from the normal alone, is
  // averaged over a cap of half vectors of radius radiusRad (a convolution on the sphere, which keeps both a
  // constant and the column's integral over half vectors) — a highlight narrower than the cap spreads over it
  // with its energy, one wider than it barely changes. The analytic lobes are regularised to GGX α = 0.09,
  // whose highlight is about atan 0.09 = 5.1° wide in θh.
  static std::shared_ptr<const BrdfTable> regularised(const BrdfTable& table, float radiusRad);

  Rgb eval(const vec3& wo, const vec3& wi) const override {
    return scale_ * table_->evalPerSr(wi, wo);
  }
  float pdf(const vec3& wo, const vec3& wi) const override;
  bool sample(const vec3& wo, float uChoice, const vec2& u, vec3& wi) const override;
  // The albedo of the θo bin of cosO (the sums that built the density).
  Rgb albedo(float cosO) const override { return albedo_[size_t(thetaOBin(cosO))]; }

 private:
  static int thetaOBin(float cosO);
  // The density per steradian of half vector h (unit, h.z > 0) for ωo in θo bin `bin` with azimuth φo.
  float halfVectorPdf(int bin, const vec3& h, float phiO) const;

  std::shared_ptr<const BrdfTable> table_;
  float scale_ = 1.0f;
  std::vector<Distribution2D> halfVectors_;  // per θo bin: rows θh, columns φh − φo
  std::vector<Rgb> albedo_;                  // per θo bin
  // 1 − cos θh at the edges of the θh rows, rising from 0 to 1 (kept as 1 − cos: the first rows are
  // narrower than float's resolution of cos θh near 1).
  std::array<float, kThetaHalfBins + 1> oneMinusCosThetaHalfEdge_{};
};

}  // namespace fly::raytracer
