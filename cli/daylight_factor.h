// The daylight factor (CIE 110-1994, BS 8206-2, EN 17037): the illuminance at a point inside under the CIE
// standard overcast sky, as a percentage of the illuminance on an unobstructed horizontal plane outside under
// the same sky:   DF = 100 % · E_inside / E_outside.
//
// The sky is the traditional CIE overcast sky (Moon & Spencer 1942, adopted by the CIE in 1955; the
// "CIE overcast sky" of daylight-factor standards and Radiance's gensky -c), whose luminance depends on the
// zenith angle θ alone:  L(θ) = Lz·(1 + 2 cos θ)/3, with no sun. Its unobstructed horizontal illuminance is
//   E = ∫ L cos θ dω = 2π Lz ∫₀¹ (1 + 2μ)/3 · μ dμ = (7π/9)·Lz.
// (ISO 15469 type 1, sunsky/cie_sky.h, approximates it with an exponential gradation; the daylight factor's
// closed forms are those of this one.)
//
// E_inside is traced (sky light through openings and its interreflections) with the sky tabulated on the
// baker's equal-area map (rdb::TraceSky): L is linear in μ = cos θ, so each cell's mean is its value at the
// cell's centre μ, exactly. E_outside is integrated from that table, not traced: E = Σ L_cell·μ_centre·2π/N²
// over its N² cells, exact for the piecewise-constant sky the integrator samples (∫ μ dμ over a cell is its
// width times its centre). So an unobstructed point has DF = 100 % up to its Monte-Carlo error; the table's
// E differs from (7π/9)·Lz by Lz·π/(9N²), 4·10⁻⁵ relative at N = 64. Electric lights, emissive surfaces and
// the sun are left out: the daylight factor is a ratio for the overcast sky alone.
#pragma once

#include <cstdint>
#include <span>

#include "rdb/trace_rdb.h"
#include "sdb/scene.h"

namespace fly::cli {

// The level of the sky fly uses, lux of unobstructed horizontal illuminance (any level gives the same
// daylight factors; 10 klx is a usual design overcast level, CIE 110-1994).
inline constexpr double kOvercastHorizontalLux = 10000.0;

// The zenith luminance, cd/m², of the CIE overcast sky with unobstructed horizontal illuminance `lux`:
// Lz = 9·E / (7π).
double overcastZenithLuminanceCdM2(double horizontalLux);

// The CIE overcast sky of zenith luminance Lz tabulated on TraceSky's map of `resolution`² cells ([1, 1024]).
rdb::TraceSky overcastSky(uint32_t resolution, double zenithLuminanceCdM2);

// The scene's daylight turned off (no sky model, no sun), so that rdb lowers no daylight of its own and the
// overcast table can be set.
void turnOffDaylight(sdb::Scene& scene);

// Leaves only the sky's light in `rdb`: no punctual lights, no sun, no emission.
void keepSkyOnly(rdb::TraceRdb& rdb);

// The horizontal illuminance of the tabulated sky on an unobstructed plane facing up, lux (see above);
// 0 for no sky.
double unobstructedHorizontalLux(const rdb::TraceSky& sky);

struct DaylightFactorSummary {
  double meanPercent = 0.0;
  double meanStdErrorPercent = 0.0;  // of the mean: √(Σ σᵢ²) / n, the points' errors being independent
  double minPercent = 0.0;
  double uniformity = 0.0;  // min / mean (EN 17037, BS 8206-2), 0 when the mean is 0
};

// The summary of per-point daylight factors (percent) and their standard errors. std::invalid_argument for
// no points or spans of different sizes.
DaylightFactorSummary summarizeDaylightFactors(std::span<const double> percent,
                                               std::span<const double> stdErrorPercent);

}  // namespace fly::cli
