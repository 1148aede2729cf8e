// The hourly skies of a weather file: for each record, the sun at the middle of its hour and the Perez
// all-weather sky and sun of its direct normal and diffuse horizontal irradiance, discretised into sky
// patches — a "sky matrix" of hours × patches, as Radiance's gendaymtx writes for daylight coefficients
// (docs/annual-daylight.md).
//
// Time: EPW records are in local STANDARD time (never daylight saving), record hour h covering [h − 1, h)
// (sunsky/epw.h). Each record's sky is computed for the sun at h − 0.5, the middle of its hour, as Radiance's
// epw2wea writes the hour for gendaymtx (hour − minutes/2 with 60-minute records) and as EnergyPlus averages
// the hour. The sun's position is the NREL SPA (sun_position.h) for that instant of a fixed reference year
// (kSolarYearWithoutLeapDay or, for files that keep 29 February, kSolarYearWithLeapDay; typical-year files
// mix years month by month, and the sun's path repeats from year to year to within 0.01°).
//
// Zero rows: a record with no diffuse horizontal irradiance (night) gives zero sky, ground and sun, as
// gendaymtx does. When the sun at mid-hour is below the horizon but the record holds diffuse light (the hours
// of sunrise and sunset), the sky is Perez's with the sun on the horizon and no direct beam (perez_sky.h);
// the record's direct normal irradiance is then not used.
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "sunsky/epw.h"
#include "sunsky/perez_sky.h"
#include "sunsky/sky_vector.h"
#include "sunsky/sun_disc.h"
#include "sunsky/sun_position.h"

namespace fly::sunsky {

inline constexpr int kSolarYearWithoutLeapDay = 2017;
inline constexpr int kSolarYearWithLeapDay = 2016;

// Turbidity that colours the sun's disc (sun_disc.h); the weather file gives only its illuminance.
inline constexpr double kWeatherSunTurbidity = 3.0;

// One record's daylight.
struct WeatherHour {
  std::size_t record = 0;          // index into EpwFile::records
  double localStandardHour = 0.5;  // the instant: record hour − 0.5, hours of its day
  int dayOfYear = 1;
  SunPosition sun;              // at that instant (apparent zenith with refraction)
  std::optional<PerezSky> sky;  // none for a record without diffuse light
  // The direct beam: Perez's direct efficacy times the record's direct normal irradiance, on the sun's
  // apparent direction; zero below the horizon and without diffuse light.
  SunDisc sunDisc;
};

// The daylight of record `record` of `file`. InputError naming the file and line for a missing direct normal
// or diffuse horizontal irradiance or one the Perez model cannot take (above the extraterrestrial value).
WeatherHour weatherHour(const EpwFile& file, std::size_t record);

struct SkyMatrixOptions {
  int multiplier = 1;       // sky subdivision (sky_patches.h): 1 = Tregenza, 2, 4 = Reinhart
  SkyVectorOptions vector;  // the sun's placement, the ground's albedo, the patch quadrature
  int threads = 0;          // rows computed in parallel, [0, 1024]; 0 = one thread per processor
};

// What the matrix row of one hour was made from.
struct SkyMatrixHour {
  int month = 1;
  int day = 1;
  int hour = 1;                          // the record's hour, 1..24
  dvec3 sunDirEnu{0.0, 0.0, 1.0};        // apparent, at mid-hour
  double sunNormalIlluminanceLux = 0.0;  // direct normal illuminance of the beam; 0 when none
  int sunPatch = kGroundPatch;        // the patch that contains the sun, kGroundPatch when it gives no light
  double diffuseHorizontalLux = 0.0;  // Perez's diffuse efficacy × the record's diffuse irradiance
};

struct SkyMatrix {
  SkyPatches patches;
  SunInPatches sunPlacement = SunInPatches::kSeparate;
  // Mean radiance per hour and patch, cd/m² per Rec.709 channel, hour-major: element h·patches.count() + p.
  // Single precision, as gendaymtx's: 8760 × 146 values take 15 MB; 8760 × 2306 (MF 4), 242 MB.
  std::vector<Rgb> radianceCdM2;
  std::vector<SkyMatrixHour> hours;  // one per record, in file order

  std::size_t hourCount() const { return hours.size(); }
  const Rgb* row(std::size_t hour) const {
    return radianceCdM2.data() + hour * static_cast<std::size_t>(patches.count());
  }
};

// The matrix of every record of `file`, about 1 ms per daylight hour and thread for MF 1 (most of it the
// Perez sky's normalisation), about 4 ms for MF 4. InputError as weatherHour (the first record in file order
// that has one), or for an option out of range.
SkyMatrix makeSkyMatrix(const EpwFile& file, const SkyMatrixOptions& options = {});

}  // namespace fly::sunsky
