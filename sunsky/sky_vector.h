// A sky discretised into the patches of a SkyPatches subdivision: each patch's mean radiance, the vector
// that daylight coefficients multiply (Radiance's genskyvec; one row of gendaymtx's sky matrix).
//
// Each sky patch is a rectangle in (μ = sin altitude, azimuth), where dω = dμ·dφ, so its mean radiance
// (1/Ω)∫ L dω is a tensor Gauss–Legendre quadrature on that rectangle. The patch that holds the sun is split
// at the sun's μ and azimuth into four, so that the kink of a circumsolar peak lies on panel edges, not
// inside a panel; the cap is integrated in (μ, φ) too, from the sun's azimuth round. Smooth skies come out to
// better than 0.1 % per patch with the default order (tests/sunsky/sky_vector_test.cpp).
//
// The ground (patch 0) is a Lambertian plane of albedo ρ lit by the sky and the sun:
// L = ρ·(E_sky,h + E_sun,h)/π, uniform over the lower hemisphere, as gendaymtx's ground (its -g option,
// default 0.2). Light is linear Rec.709 RGB with luminance in cd/m² (docs/architecture.md).
#pragma once

#include <vector>

#include "sunsky/sky.h"
#include "sunsky/sky_patches.h"
#include "sunsky/sun_disc.h"

namespace fly::sunsky {

// Where a vector puts the sun's direct light.
enum class SunInPatches {
  // Not in the patches: they hold the sky and the ground; the caller traces the sun on its own (exact
  // direction and disc, and the direct-sun-only illuminance that annual sunlight exposure needs).
  kSeparate,
  // Added to the one patch that contains the sun's centre, as the radiance E_sun / Ω_patch that gives the
  // patch the sun's normal illuminance. (gendaymtx spreads it over the 4 patches nearest the sun, weighted
  // 1 / (1.002 − cos γ); genskyvec over the nearest 3, weighted 1 / (γ + 0.02); both blur the sun's position
  // to about a patch width as well.)
  kContainingPatch,
};

// Gauss–Legendre nodes per patch and axis (μ and azimuth): 6 × 6 per patch, 4 × 6 × 6 in the sun's patch.
inline constexpr int kDefaultPatchNodes = 6;

struct SkyVectorOptions {
  SunInPatches sun = SunInPatches::kSeparate;
  double groundAlbedo = 0.2;              // [0, 1], the ground patch's reflectance (gendaymtx's default)
  int nodesPerAxis = kDefaultPatchNodes;  // [1, 32]
};

struct SkyVector {
  // Mean radiance of each patch, indexed as SkyPatches (0 = the ground), cd/m² per Rec.709 channel.
  std::vector<dvec3> radianceCdM2;
  // The sun given, with the patch that contains its centre (kGroundPatch when it is below the horizon).
  SunDisc sun;
  int sunPatch = kGroundPatch;
  SunInPatches sunPlacement = SunInPatches::kSeparate;

  // Luminance of patch i's mean radiance, cd/m².
  double luminanceCdM2(int i) const;
};

// The vector of `sky` and `sun` (a SunDisc{} of zero illuminance for none) over `patches`. InputError for an
// option out of range.
SkyVector makeSkyVector(const Sky& sky, const SunDisc& sun, const SkyPatches& patches,
                        const SkyVectorOptions& options = {});

// Illuminance on an unobstructed horizontal plane from the sky patches, lux: Σ L_i·projectedSolidAngleSr_i
// (the ground lights nothing from below). With SunInPatches::kSeparate it is the sky's alone; add
// E_sun·cos θ_sun for the global value.
double horizontalIlluminanceLux(const SkyVector& vector, const SkyPatches& patches);

}  // namespace fly::sunsky
