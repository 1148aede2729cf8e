// Isotropic measured BRDFs in the MERL format (Matusik, Pfister, Brand and McMillan 2003, "A Data-Driven
// Reflectance Model", SIGGRAPH; the format of the MERL BRDF database and its reference reader BRDFRead.cpp).
//
// A MERL file is three little-endian int32 dimensions (90, 90, 180) and then 3 · 90 · 90 · 180 doubles: the red,
// green and blue tables one after the other, each indexed [θh][θd][φd] (φd fastest), in the half/difference
// angles of Rusinkiewicz (1998, "A New Change of Variables for Efficient BRDF Representation"). Sample
// (i, j, k) lies at
//   θh = (i / 90)² · π/2     (dense near the highlight, where the BRDF changes fastest)
//   θd = j / 90 · π/2
//   φd = k / 180 · π         (φd and φd + π are the same by reciprocity, so half a turn is stored)
// and stored values times the channel's scale (1/1500, 1.15/1500, 1.66/1500) are the BRDF in 1/sr.
// Reflectance is RGB in fly's linear Rec.709 with photometric luminance (docs/architecture.md), which is how
// fly reads the three channels.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <vector>

#include "base/color.h"
#include "base/math.h"

namespace fly::sdb {

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

class MeasuredBrdf {
 public:
  static constexpr int kThetaHalfRes = 90;
  static constexpr int kThetaDiffRes = 90;
  static constexpr int kPhiDiffRes = 180;
  static constexpr size_t kSamples = size_t(kThetaHalfRes) * kThetaDiffRes * kPhiDiffRes;
  // MERL's per-channel scales from stored values to 1/sr (BRDFRead.cpp: RED_SCALE, GREEN_SCALE, BLUE_SCALE).
  static constexpr double kChannelScale[3] = {1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0};

  // The BRDF at every sample, 1/sr, finite and ≥ 0: kSamples values, index sampleIndex(i, j, k).
  explicit MeasuredBrdf(std::vector<Rgb> samplesPerSr);

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

// Reads a MERL binary file. Throws InputError naming the file when it cannot be read, its dimensions are not
// 90 × 90 × 180, its size does not match them, or a value is NaN, infinite or negative (the first one is
// named by channel and angles).
MeasuredBrdf readMerlBrdf(const std::filesystem::path& file);

// Writes a MERL binary file (atomically) whose sample (i, j, k) is brdfPerSr(MeasuredBrdf::sampleAngles(i, j,
// k)) — for tables made from analytic BRDFs in tests and tools.
void writeMerlBrdf(const std::filesystem::path& file, const std::function<Rgb(const HalfDiffAngles&)>& brdfPerSr);

}  // namespace fly::sdb
