#include "sunsky/sky_patches.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "base/error.h"
#include "sunsky/site_frame.h"

namespace fly::sunsky {

namespace {

// Tregenza's patches per band from the horizon up, before the cap (reinhart.cal's tnaz).
constexpr int kTregenzaBandPatches[7] = {30, 30, 24, 24, 18, 12, 6};

}  // namespace

int SkyPatches::bandPatchCount(int band) const {
  const int next = band + 1 < bandCount() ? bandFirstPatch(band + 1) : count();
  return next - bandFirstPatch(band);
}

int SkyPatches::patchIndex(const dvec3& dirEnu) const {
  if (!(dirEnu.z >= 0.0)) return kGroundPatch;
  const double z = dirEnu.z / glm::length(dirEnu);
  const int capBand = bandCount() - 1;
  // reinhart.cal: band ⌊altitude / α⌋; then settled against the stored band edges so that the index agrees
  // with the patch bounds even where rounding puts asin on the other side of an edge.
  int band = static_cast<int>(std::floor(radToDeg(std::asin(std::min(z, 1.0))) / bandWidthDeg_));
  band = std::clamp(band, 0, capBand);
  while (band > 0 && z < bandSinLower_[static_cast<std::size_t>(band)]) --band;
  while (band < capBand && z >= bandSinLower_[static_cast<std::size_t>(band + 1)]) ++band;
  if (band == capBand) return count() - 1;

  const int n = bandPatchCount(band);
  double azimuth = std::atan2(dirEnu.x, dirEnu.y);  // clockwise from north, (−π, π]
  if (azimuth < 0.0) azimuth += 2.0 * kPi;
  const double width = 2.0 * kPi / n;
  int column = static_cast<int>(std::floor((azimuth + 0.5 * width) / width));
  if (column >= n) column -= n;  // the last half-width before north belongs to the patch centred on north
  return bandFirstPatch(band) + column;
}

SkyPatches makeSkyPatches(int multiplier) {
  if (multiplier < 1 || multiplier > kMaxSkyMultiplier) {
    throw InputError({}, "unknown sky subdivision: multiplier " + std::to_string(multiplier),
                     "give 1 (Tregenza, 145 patches), 2 (Reinhart, 577), 4 (Reinhart, 2305) or another "
                     "multiplier from 1 to " +
                         std::to_string(kMaxSkyMultiplier));
  }
  SkyPatches s;
  s.multiplier_ = multiplier;
  const int bands = 7 * multiplier;
  s.bandWidthDeg_ = 90.0 / (bands + 0.5);
  const double alpha = degToRad(s.bandWidthDeg_);

  SkyPatch ground;
  ground.centreDirEnu = dvec3(0.0, 0.0, -1.0);
  ground.solidAngleSr = 2.0 * kPi;
  ground.projectedSolidAngleSr = 0.0;
  ground.minAltitudeDeg = -90.0;
  ground.maxAltitudeDeg = 0.0;
  s.patches_.push_back(ground);

  for (int band = 0; band < bands; ++band) {
    const int n = multiplier * kTregenzaBandPatches[band / multiplier];
    const double sin0 = std::sin(band * alpha);
    const double sin1 = std::sin((band + 1) * alpha);
    s.bandSinLower_.push_back(sin0);
    s.bandFirstPatch_.push_back(static_cast<int>(s.patches_.size()));
    const double widthDeg = 360.0 / n;
    for (int c = 0; c < n; ++c) {
      SkyPatch p;
      p.centreDirEnu = directionFromAzimuthElevation(c * widthDeg, (band + 0.5) * s.bandWidthDeg_);
      p.solidAngleSr = 2.0 * kPi * (sin1 - sin0) / n;
      p.projectedSolidAngleSr = kPi * (sin1 * sin1 - sin0 * sin0) / n;
      p.minAltitudeDeg = band * s.bandWidthDeg_;
      p.maxAltitudeDeg = (band + 1) * s.bandWidthDeg_;
      p.minAzimuthDeg = (c - 0.5) * widthDeg;
      p.maxAzimuthDeg = (c + 0.5) * widthDeg;
      p.band = band;
      s.patches_.push_back(p);
    }
  }

  // The cap: angular radius α/2 about the zenith (genskyvec's Romega = 2π(1 − cos(α/2))); its lower edge, at
  // altitude 7·MF·α = 90° − α/2, is computed as the top band's upper edge so that the two agree to the bit.
  const double capSinLower = std::sin(bands * alpha);
  s.bandSinLower_.push_back(capSinLower);
  s.bandFirstPatch_.push_back(static_cast<int>(s.patches_.size()));
  SkyPatch cap;
  cap.centreDirEnu = dvec3(0.0, 0.0, 1.0);
  cap.solidAngleSr = 2.0 * kPi * (1.0 - capSinLower);
  cap.projectedSolidAngleSr = kPi * (1.0 - capSinLower * capSinLower);
  cap.minAltitudeDeg = 90.0 - 0.5 * s.bandWidthDeg_;
  cap.maxAltitudeDeg = 90.0;
  cap.minAzimuthDeg = 0.0;
  cap.maxAzimuthDeg = 360.0;
  cap.band = bands;
  s.patches_.push_back(cap);
  return s;
}

}  // namespace fly::sunsky
