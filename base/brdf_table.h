// An isotropic BRDF tabulated in the half/difference angles of Rusinkiewicz (1998, "A New Change of Variables
// for Efficient BRDF Representation"), on the grid of the MERL BRDF database (Matusik, Pfister, Brand and
// McMillan 2003, "A Data-Driven Reflectance Model", SIGGRAPH): 90 × 90 × 180 RGB samples indexed
// [θh][θd][φd] (φd fastest). Sample (i, j, k) lies at
//   θh = (i / 90)² · π/2     (dense near the highlight, where the BRDF changes fastest)
//   θd = j / 90 · π/2
//   φd = k / 180 · π         (φd and φd + π are the same by reciprocity, so half a turn is stored)
// and holds the BRDF in 1/sr, linear Rec.709 RGB. The SDB reads such tables from MERL files
// (sdb/measured_brdf.h); the baker evaluates and samples them (raytracer/tabulated_lobe.h). Both need this
// math, so it lives in base.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "base/color.h"
#include "base/math.h"

namespace fly {

// Rusinkiewicz's half/difference angles of a pair of directions in a surface's local frame (z = normal).
struct HalfDiffAngles {
  float thetaHalfRad = 0.0f;  // angle of the half vector from the normal, [0, π/2]
  float thetaDiffRad = 0.0f;  // angle of the incident direction from the half vector, [0, π/2]
  float phiDiffRad = 0.0f;    // azimuth of the incident direction around the half vector, [0, 2π)
};

// Both directions unit and in the upper hemisphere (z > 0) of the local frame.
HalfDiffAngles halfDiffAngles(const vec3& wiLocal, const vec3& woLocal);

// The incident and outgoing directions (local frame) of half/difference angles (φh = 0): the inverse of
// halfDiffAngles for an isotropic BRDF.
void directionsOf(const HalfDiffAngles& a, vec3& wiLocal, vec3& woLocal);

class BrdfTable {
 public:
  static constexpr int kThetaHalfRes = 90;
  static constexpr int kThetaDiffRes = 90;
  static constexpr int kPhiDiffRes = 180;
  static constexpr size_t kSamples = size_t(kThetaHalfRes) * kThetaDiffRes * kPhiDiffRes;

  // The BRDF at every sample, 1/sr, finite and ≥ 0: kSamples values, index sampleIndex(i, j, k).
  // std::invalid_argument for another count.
  explicit BrdfTable(std::vector<Rgb> samplesPerSr);

  static size_t sampleIndex(int thetaHalf, int thetaDiff, int phiDiff) {
    return (size_t(thetaHalf) * kThetaDiffRes + size_t(thetaDiff)) * kPhiDiffRes + size_t(phiDiff);
  }
  // The angles of sample (i, j, k) (see the file's header).
  static HalfDiffAngles sampleAngles(int thetaHalf, int thetaDiff, int phiDiff);

  const Rgb& sample(int thetaHalf, int thetaDiff, int phiDiff) const {
    return samples_[sampleIndex(thetaHalf, thetaDiff, phiDiff)];
  }

  // The BRDF in 1/sr for unit directions in the local frame (z = normal), interpolated trilinearly between
  // samples in (√(θh/(π/2)), θd, φd) — the table's own coordinates, periodic in φd with period π — over the
  // corners whose own directions lie above the surface (the others were never measured); 0 when either
  // direction lies below the surface (z ≤ 0). MERL's reference reader takes the sample below instead
  // (nearestSample), which steps visibly in a sharp highlight.
  Rgb evalPerSr(const vec3& wiLocal, const vec3& woLocal) const;
  Rgb nearestSample(const vec3& wiLocal, const vec3& woLocal) const;

  // Directional albedo ρ(θi) = ∫ f(ωi, ωo) cos θo dωo over the upper hemisphere, per channel, by midpoint
  // quadrature on a cosine-weighted grid of `thetaSteps` × 4·thetaSteps cells (sin θo = √u, φo = 2πv).
  Rgb albedo(float cosThetaIn, int thetaSteps = 96) const;

  // The largest directional albedo of any channel over incident angles θi = 0°, 5°, … 85°, 89°, and where.
  struct AlbedoPeak {
    float albedo = 0.0f;
    float thetaInDeg = 0.0f;
    int channel = 0;  // 0 red, 1 green, 2 blue
  };
  AlbedoPeak maxAlbedo(int thetaSteps = 96) const;

  // 1 for the samples whose incident and outgoing directions both lie above the surface, indexed as samples.
  static const std::vector<uint8_t>& validSamples();

 private:
  std::vector<Rgb> samples_;
};

}  // namespace fly
