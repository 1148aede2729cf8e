// The sky dome divided into patches for daylight coefficients: Tregenza's 145 patches (Tregenza, "Subdivision
// of the sky hemisphere for luminance measurements", Lighting Research & Technology 19(1) (1987) 13–14) and
// Reinhart's subdivisions of them, exactly as Radiance's reinhart.cal, genskyvec and gendaymtx number them.
//
// With the multiplier MF (1 = Tregenza), the sky has 7·MF bands of equal altitude width
// α = 90° / (7·MF + 0.5), band r (0 at the horizon) holding MF·n(⌊r / MF⌋) patches, n = 30, 30, 24, 24, 18,
// 12, 6, and a cap of one patch of angular radius α/2 around the zenith: 145, 577 and 2305 patches for MF 1,
// 2 and 4 (MF² · 144 + 1).
//
// Numbering (Radiance's "bin"): index 0 is the ground, the whole lower hemisphere (2π sr), as in genskyvec
// and gendaymtx; the sky patches follow from 1, band by band from the horizon up, the cap last. Within a
// band, patch 1 of the band is centred on north (azimuth 0) and the numbers run towards the east (clockwise
// seen from above); a band of n patches spans azimuths [(c − ½)·360°/n, (c + ½)·360°/n) for its c-th patch,
// c = 0..n−1. Reinhart.cal computes the same with azimuth atan2(Dx, Dy), Dx east and Dy north.
#pragma once

#include <vector>

#include "base/math.h"

namespace fly::sunsky {

inline constexpr int kGroundPatch = 0;

struct SkyPatch {
  // Unit ENU direction of the patch centre: the band's mid-altitude at the patch's mid-azimuth (genskyvec's
  // and gendaymtx's patch direction); the zenith for the cap; straight down for the ground.
  dvec3 centreDirEnu{0.0, 0.0, 1.0};
  // ∫ dω over the patch, sr, exact: 2π·(sin a₁ − sin a₀) / n for a band [a₀, a₁] of n patches,
  // 2π·(1 − cos(α/2)) for the cap, 2π for the ground.
  double solidAngleSr = 0.0;
  // ∫ cos θ dω over the patch (θ from the zenith), sr, exact: π·(sin² a₁ − sin² a₀) / n for a band,
  // π·sin²(α/2) for the cap; 0 for the ground (it lights no horizontal surface from below). The sky
  // patches' values sum to π. The centre's cos θ times the solid angle overestimates it by 1 / cos(α/2) in
  // every band (0.55 % for Tregenza's α = 12°): use this for the illuminance of a patch of uniform radiance.
  double projectedSolidAngleSr = 0.0;
  // Bounds: altitude [minAltitudeDeg, maxAltitudeDeg) (the cap includes 90°), azimuth clockwise from north
  // [minAzimuthDeg, maxAzimuthDeg), which may start below 0 (the patches centred on north start at −½ width).
  // The cap spans the full circle; the ground has altitude [−90, 0).
  double minAltitudeDeg = 0.0;
  double maxAltitudeDeg = 0.0;
  double minAzimuthDeg = 0.0;
  double maxAzimuthDeg = 360.0;
  int band = -1;  // 0..7·MF − 1 for the bands, 7·MF for the cap, −1 for the ground
};

class SkyPatches {
 public:
  int multiplier() const { return multiplier_; }
  // Patches including the ground: 146, 578, 2306 for MF 1, 2, 4 (genskyvec's Nrbins).
  int count() const { return static_cast<int>(patches_.size()); }
  // Sky patches only: count() − 1.
  int skyCount() const { return count() - 1; }
  // Bands including the cap: 7·MF + 1.
  int bandCount() const { return static_cast<int>(bandFirstPatch_.size()); }
  // Altitude width α of a band, degrees.
  double bandWidthDeg() const { return bandWidthDeg_; }
  const SkyPatch& operator[](int index) const { return patches_[static_cast<std::size_t>(index)]; }
  const std::vector<SkyPatch>& patches() const { return patches_; }
  // Index of the first patch of band b and the number of patches in it.
  int bandFirstPatch(int band) const { return bandFirstPatch_[static_cast<std::size_t>(band)]; }
  int bandPatchCount(int band) const;

  // The patch that contains the direction (any non-zero vector, ENU): the ground for dirEnu.z < 0, a sky
  // patch from altitude 0 up (reinhart.cal's rbin). Allocation-free.
  int patchIndex(const dvec3& dirEnu) const;

 private:
  friend SkyPatches makeSkyPatches(int);
  int multiplier_ = 1;
  double bandWidthDeg_ = 12.0;
  std::vector<double> bandSinLower_;  // sin of each band's lower altitude, plus the cap's
  std::vector<int> bandFirstPatch_;
  std::vector<SkyPatch> patches_;
};

// The subdivision with multiplier `multiplier`: 1 = Tregenza (145 sky patches), 2 = Reinhart 577, 4 =
// Reinhart 2305, or any other in 1..kMaxSkyMultiplier (MF 3: 1297, MF 8: 9217). InputError outside.
inline constexpr int kMaxSkyMultiplier = 8;
SkyPatches makeSkyPatches(int multiplier);

}  // namespace fly::sunsky
