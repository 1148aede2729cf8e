#include "base/brdf_table.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace fly {
namespace {

constexpr double kHalfPi = 1.57079632679489661923;

// v rotated by `angle` about the unit `axis` (Rodrigues' formula).
dvec3 rotate(const dvec3& v, const dvec3& axis, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return v * c + axis * glm::dot(axis, v) * (1.0 - c) + glm::cross(axis, v) * s;
}

// The angle of unit vector v from +z, accurate near 0 (acos loses half its digits there, and the table's
// θh samples start at 0.011°).
double angleFromZ(const dvec3& v) { return std::atan2(std::sqrt(v.x * v.x + v.y * v.y), v.z); }

// Continuous table coordinates of a pair of directions: (√(θh/(π/2))·90, θd/(π/2)·90, φd/π·180 in [0, 180)).
dvec3 tableCoordinates(const vec3& wiLocal, const vec3& woLocal) {
  const HalfDiffAngles a = halfDiffAngles(wiLocal, woLocal);
  double phi = std::fmod(double(a.phiDiffRad), kPi);
  if (phi < 0.0) phi += kPi;
  return {std::sqrt(std::max(0.0, double(a.thetaHalfRad) / kHalfPi)) * BrdfTable::kThetaHalfRes,
          double(a.thetaDiffRad) / kHalfPi * BrdfTable::kThetaDiffRes, phi / kPi * BrdfTable::kPhiDiffRes};
}

}  // namespace

HalfDiffAngles halfDiffAngles(const vec3& wiLocal, const vec3& woLocal) {
  const dvec3 wi(wiLocal), wo(woLocal);
  const dvec3 half = glm::normalize(wi + wo);
  // Rotate ωi so that the half vector becomes the normal: by −φh about the normal, then −θh about the
  // binormal (Rusinkiewicz 1998, §3; BRDFRead.cpp std_coords_to_half_diff_coords), with the rotations' cosines
  // and sines read off the unit half vector (cos φh = h.x / sin θh, sin θh = |h.xy|, cos θh = h.z) rather
  // than computed from its angles.
  const double sinThetaHalf = std::sqrt(half.x * half.x + half.y * half.y);
  const double cosPhiHalf = sinThetaHalf > 0.0 ? half.x / sinThetaHalf : 1.0;
  const double sinPhiHalf = sinThetaHalf > 0.0 ? half.y / sinThetaHalf : 0.0;
  const dvec3 turned(wi.x * cosPhiHalf + wi.y * sinPhiHalf, wi.y * cosPhiHalf - wi.x * sinPhiHalf, wi.z);
  const dvec3 diff(turned.x * half.z - turned.z * sinThetaHalf, turned.y,
                   turned.z * half.z + turned.x * sinThetaHalf);
  double phiDiff = std::atan2(diff.y, diff.x);
  if (phiDiff < 0.0) phiDiff += 2.0 * kPi;
  return {float(std::atan2(sinThetaHalf, half.z)), float(angleFromZ(diff)), float(phiDiff)};
}

void directionsOf(const HalfDiffAngles& a, vec3& wiLocal, vec3& woLocal) {
  const double st = std::sin(double(a.thetaDiffRad));
  const dvec3 diff(st * std::cos(double(a.phiDiffRad)), st * std::sin(double(a.phiDiffRad)),
                   std::cos(double(a.thetaDiffRad)));
  const dvec3 half(std::sin(double(a.thetaHalfRad)), 0.0, std::cos(double(a.thetaHalfRad)));
  const dvec3 wi = rotate(diff, dvec3(0, 1, 0), double(a.thetaHalfRad));
  wiLocal = vec3(wi);
  woLocal = vec3(2.0 * glm::dot(wi, half) * half - wi);
}

BrdfTable::BrdfTable(std::vector<Rgb> samplesPerSr) : samples_(std::move(samplesPerSr)) {
  if (samples_.size() != kSamples) throw std::invalid_argument("BrdfTable: wrong number of samples");
}

HalfDiffAngles BrdfTable::sampleAngles(int thetaHalf, int thetaDiff, int phiDiff) {
  const double h = double(thetaHalf) / kThetaHalfRes;
  return {float(h * h * kHalfPi), float(double(thetaDiff) / kThetaDiffRes * kHalfPi),
          float(double(phiDiff) / kPhiDiffRes * kPi)};
}

Rgb BrdfTable::evalPerSr(const vec3& wiLocal, const vec3& woLocal) const {
  if (!(wiLocal.z > 0.0f) || !(woLocal.z > 0.0f)) return Rgb(0.0f);
  const dvec3 c = tableCoordinates(wiLocal, woLocal);
  // θh and θd: linear between samples, the last sample held beyond it; φd periodic.
  auto split = [](double x, int res, int& i0, int& i1, float& f) {
    x = std::clamp(x, 0.0, double(res - 1));
    i0 = std::min(int(x), res - 2);
    i1 = i0 + 1;
    f = float(x - i0);
  };
  int h0, h1, d0, d1;
  float fh, fd;
  split(c.x, kThetaHalfRes, h0, h1, fh);
  split(c.y, kThetaDiffRes, d0, d1, fd);
  const double z = std::clamp(c.z, 0.0, double(kPhiDiffRes));
  const int p0 = std::min(int(z), kPhiDiffRes - 1);
  const int p1 = (p0 + 1) % kPhiDiffRes;
  const float fp = float(z - p0);
  // Corners whose own directions lie below the surface hold no measurement (a table written from a formula
  // may hold 0 there): they are left out and the other corners' weights renormalised.
  const std::vector<uint8_t>& valid = validSamples();
  Rgb sum(0.0f);
  float weightSum = 0.0f;
  for (int corner = 0; corner < 8; ++corner) {
    const int h = corner & 1 ? h1 : h0, d = corner & 2 ? d1 : d0, p = corner & 4 ? p1 : p0;
    const float w = (corner & 1 ? fh : 1.0f - fh) * (corner & 2 ? fd : 1.0f - fd) * (corner & 4 ? fp : 1.0f - fp);
    const size_t s = sampleIndex(h, d, p);
    if (w > 0.0f && valid[s]) {
      sum += w * samples_[s];
      weightSum += w;
    }
  }
  return weightSum > 0.0f ? sum / weightSum : sample(h0, d0, p0);
}

const std::vector<uint8_t>& BrdfTable::validSamples() {
  static const std::vector<uint8_t> valid = [] {
    std::vector<uint8_t> v(kSamples);
    for (int i = 0; i < kThetaHalfRes; ++i) {
      for (int j = 0; j < kThetaDiffRes; ++j) {
        for (int k = 0; k < kPhiDiffRes; ++k) {
          vec3 wi, wo;
          directionsOf(sampleAngles(i, j, k), wi, wo);
          v[sampleIndex(i, j, k)] = wi.z > 0.0f && wo.z > 0.0f;
        }
      }
    }
    return v;
  }();
  return valid;
}

Rgb BrdfTable::nearestSample(const vec3& wiLocal, const vec3& woLocal) const {
  if (!(wiLocal.z > 0.0f) || !(woLocal.z > 0.0f)) return Rgb(0.0f);
  const dvec3 c = tableCoordinates(wiLocal, woLocal);
  return sample(std::clamp(int(c.x), 0, kThetaHalfRes - 1), std::clamp(int(c.y), 0, kThetaDiffRes - 1),
                std::clamp(int(c.z), 0, kPhiDiffRes - 1));
}

Rgb BrdfTable::albedo(float cosThetaIn, int thetaSteps) const {
  const float c = std::clamp(cosThetaIn, 1e-4f, 1.0f);
  const vec3 wi(std::sqrt(1.0f - c * c), 0.0f, c);
  const int n = std::max(thetaSteps, 1);
  const int m = 4 * n;
  dvec3 sum(0.0);
  for (int a = 0; a < n; ++a) {
    const double u = (a + 0.5) / n;
    const double sinTheta = std::sqrt(u), cosTheta = std::sqrt(1.0 - u);
    for (int b = 0; b < m; ++b) {
      const double phi = 2.0 * kPi * (b + 0.5) / m;
      const vec3 wo(float(sinTheta * std::cos(phi)), float(sinTheta * std::sin(phi)), float(cosTheta));
      sum += dvec3(evalPerSr(wi, wo));
    }
  }
  // Cosine-weighted cells: ∫ f cos θ dω = π · mean f.
  return Rgb(sum * (kPi / (double(n) * m)));
}

BrdfTable::AlbedoPeak BrdfTable::maxAlbedo(int thetaSteps) const {
  AlbedoPeak peak;
  std::vector<float> anglesDeg;
  for (int d = 0; d <= 85; d += 5) anglesDeg.push_back(float(d));
  anglesDeg.push_back(89.0f);
  for (float deg : anglesDeg) {
    const Rgb a = albedo(std::cos(float(deg * kPi / 180.0)), thetaSteps);
    for (int ch = 0; ch < 3; ++ch) {
      if (a[ch] > peak.albedo) peak = {a[ch], deg, ch};
    }
  }
  return peak;
}

}  // namespace fly
