#include "cli/studio_environment.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "base/math.h"

namespace fly::cli {
namespace {

constexpr double kDegree = kPi / 180.0;

struct Softbox {
  double azimuthDeg, elevationDeg;  // its centre
  double widthDeg, heightDeg;       // along its horizontal axis and across it
  float luminanceCdM2;
};

// The key, fill and top strip (studio_environment.h).
constexpr Softbox kSoftboxes[] = {
    {45.0, 30.0, 30.0, 40.0, 4000.0f},
    {300.0, 15.0, 20.0, 40.0, 1200.0f},
    {180.0, 75.0, 12.0, 80.0, 2500.0f},
};
constexpr float kDomeCdM2 = 30.0f;
constexpr float kFloorCdM2 = 10.0f;

vec3 direction(double azimuthRad, double elevationRad) {
  return vec3(float(std::cos(elevationRad) * std::cos(azimuthRad)), float(std::sin(elevationRad)),
              float(std::cos(elevationRad) * std::sin(azimuthRad)));
}

// Whether unit direction d lies on softbox s: its angles along the box's horizontal axis u and its vertical
// axis v, seen from the centre direction c, within half the box's width and height.
bool onSoftbox(const Softbox& s, const vec3& d) {
  const double az = s.azimuthDeg * kDegree, el = s.elevationDeg * kDegree;
  const vec3 c = direction(az, el);
  const vec3 u = glm::normalize(glm::cross(vec3(0, 1, 0), c));  // horizontal
  const vec3 v = glm::cross(c, u);
  const double along = glm::dot(d, c);
  if (along <= 0.0) return false;
  return std::abs(std::atan2(glm::dot(d, u), along)) <= 0.5 * s.widthDeg * kDegree &&
         std::abs(std::atan2(glm::dot(d, v), along)) <= 0.5 * s.heightDeg * kDegree;
}

float studioRadiance(const vec3& d) {
  for (const Softbox& s : kSoftboxes) {
    if (onSoftbox(s, d)) return s.luminanceCdM2;
  }
  return d.y >= 0.0f ? kDomeCdM2 : kFloorCdM2;
}

}  // namespace

rdb::RasterSky studioEnvironment(uint32_t width, uint32_t height) {
  if (width < 4 || width > 8192 || height < 2 || height > 4096) {
    throw std::invalid_argument("studio environment size " + std::to_string(width) + "×" + std::to_string(height) +
                                " is out of range ([4, 8192] × [2, 4096])");
  }
  rdb::RasterSky sky;
  sky.width = width;
  sky.height = height;
  sky.radianceCdM2.resize(size_t(width) * height);
  constexpr int kSub = 4;
  for (uint32_t y = 0; y < height; ++y) {
    const double cos0 = std::cos(kPi * y / height), cos1 = std::cos(kPi * (y + 1) / height);
    for (uint32_t x = 0; x < width; ++x) {
      double sum = 0.0;
      for (int j = 0; j < kSub; ++j) {
        const double cosTheta = cos0 + (cos1 - cos0) * (j + 0.5) / kSub;
        const double sinTheta = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
        for (int i = 0; i < kSub; ++i) {
          const double phi = 2.0 * kPi * (x + (i + 0.5) / kSub) / width;
          sum += studioRadiance(vec3(float(sinTheta * std::cos(phi)), float(cosTheta), float(sinTheta * std::sin(phi))));
        }
      }
      sky.radianceCdM2[size_t(y) * width + x] = Rgb(float(sum / (kSub * kSub)));
    }
  }
  return sky;
}

}  // namespace fly::cli
