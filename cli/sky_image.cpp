#include "cli/sky_image.h"

#include <cmath>
#include <vector>

namespace fly::cli {

namespace {

// Image position (pixels from the top-left corner) of a direction above the horizon.
dvec2 fisheyePosition(const dvec3& dirEnu, int size) {
  const double theta = std::acos(std::clamp(dirEnu.z, -1.0, 1.0));
  const double horizontal = std::hypot(dirEnu.x, dirEnu.y);
  const double r = theta / (kPi / 2.0);  // 0 at the zenith, 1 at the horizon
  // East (+x) is on the left, north (+y) up.
  const double x = horizontal > 0.0 ? -dirEnu.x / horizontal * r : 0.0;
  const double y = horizontal > 0.0 ? dirEnu.y / horizontal * r : 0.0;
  const double half = size / 2.0;
  return {half + x * half, half - y * half};
}

}  // namespace

std::optional<dvec3> fisheyeDirection(double u, double v, int size) {
  const double half = size / 2.0;
  const double x = (u - half) / half;
  const double y = (half - v) / half;
  const double r = std::hypot(x, y);
  if (r > 1.0) return std::nullopt;
  const double theta = r * (kPi / 2.0);
  if (r == 0.0) return dvec3(0.0, 0.0, 1.0);
  const double s = std::sin(theta) / r;
  return dvec3(-x * s, y * s, std::cos(theta));
}

double fisheyePixelSolidAngle(double thetaRad, int size) {
  const double sinc = thetaRad > 1e-8 ? std::sin(thetaRad) / thetaRad : 1.0;
  return (kPi / size) * (kPi / size) * sinc;
}

ImageRgbF renderSkyFisheye(const sunsky::Sky& sky, const std::optional<sunsky::SunDisc>& sun, int size) {
  ImageRgbF img;
  img.width = size;
  img.height = size;
  img.rgb.assign(size_t(size) * size_t(size) * 3, 0.0f);
  for (int row = 0; row < size; ++row) {
    for (int col = 0; col < size; ++col) {
      Rgb sum(0.0f);
      int inside = 0;
      for (int s = 0; s < 4; ++s) {
        const std::optional<dvec3> dir =
            fisheyeDirection(col + 0.25 + 0.5 * (s & 1), row + 0.25 + 0.5 * (s >> 1), size);
        if (!dir) continue;
        sum += sky.radianceCdM2(*dir);
        ++inside;
      }
      // Pixels cut by the horizon circle keep the mean of their samples inside it.
      if (inside == 0) continue;
      const Rgb mean = sum / float(inside);
      float* p = &img.rgb[(size_t(row) * size_t(size) + size_t(col)) * 3];
      p[0] = mean.r;
      p[1] = mean.g;
      p[2] = mean.b;
    }
  }
  if (sun && sun->dirEnu.z > 0.0 && luminance(sun->normalIlluminanceLux) > 0.0f) {
    const dvec2 c = fisheyePosition(sun->dirEnu, size);
    const double cosRadius = std::cos(degToRad(sunsky::kSunAngularDiameterDeg / 2.0));
    std::vector<std::pair<int, int>> pixels;
    const int c0 = std::clamp(int(c.x), 0, size - 1);
    const int r0 = std::clamp(int(c.y), 0, size - 1);
    const int reach = 2 + int(degToRad(sunsky::kSunAngularDiameterDeg) / (kPi / size));
    for (int row = std::max(0, r0 - reach); row <= std::min(size - 1, r0 + reach); ++row) {
      for (int col = std::max(0, c0 - reach); col <= std::min(size - 1, c0 + reach); ++col) {
        const std::optional<dvec3> dir = fisheyeDirection(col + 0.5, row + 0.5, size);
        if (dir && glm::dot(*dir, sun->dirEnu) >= cosRadius) pixels.emplace_back(row, col);
      }
    }
    if (pixels.empty()) pixels.emplace_back(r0, c0);
    // Each pixel gets an equal share of the disc's normal illuminance E: L = E / (n · Ω), so Σ L·Ω = E.
    for (const auto& [row, col] : pixels) {
      const std::optional<dvec3> dir = fisheyeDirection(col + 0.5, row + 0.5, size);
      const double theta = dir ? std::acos(std::clamp(dir->z, -1.0, 1.0)) : kPi / 2.0;
      const double share = 1.0 / (double(pixels.size()) * fisheyePixelSolidAngle(theta, size));
      float* p = &img.rgb[(size_t(row) * size_t(size) + size_t(col)) * 3];
      for (int ch = 0; ch < 3; ++ch) p[ch] += float(sun->normalIlluminanceLux[ch] * share);
    }
  }
  return img;
}

double fisheyeHorizontalIlluminanceLux(const ImageRgbF& image) {
  double sum = 0.0;
  for (int row = 0; row < image.height; ++row) {
    for (int col = 0; col < image.width; ++col) {
      const std::optional<dvec3> dir = fisheyeDirection(col + 0.5, row + 0.5, image.width);
      if (!dir) continue;
      const float* p = &image.rgb[(size_t(row) * size_t(image.width) + size_t(col)) * 3];
      const double theta = std::acos(std::clamp(dir->z, -1.0, 1.0));
      sum += luminance(Rgb(p[0], p[1], p[2])) * dir->z * fisheyePixelSolidAngle(theta, image.width);
    }
  }
  return sum;
}

}  // namespace fly::cli
