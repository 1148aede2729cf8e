// EnergyPlus weather files (EPW): the site, its time zone and the hourly weather, radiation and daylight.
//
// Format: EnergyPlus Auxiliary Programs documentation, "Weather Converter Program", section "EnergyPlus
// Weather File (EPW) Data Dictionary". Eight header lines (LOCATION, DESIGN CONDITIONS, TYPICAL/EXTREME
// PERIODS, GROUND TEMPERATURES, HOLIDAYS/DAYLIGHT SAVINGS, COMMENTS 1, COMMENTS 2, DATA PERIODS), then one
// comma-separated line of 35 fields per hour: 8760 for a year (8784 with 29 February). Files of part of a
// year are read as well, as long as their DATA PERIODS line says so; the hours must follow each other without
// gaps.
//
// Time: EPW hours are LOCAL STANDARD TIME, never daylight-saving time, at EpwLocation::timeZoneHours from
// UTC. Record hour h (1..24) holds what was observed or summed over the PRECEDING hour, [h − 1, h) local
// standard time ("Hour 1 is 00:01 to 01:00"; radiation "received ... during the number of minutes preceding
// the time indicated"), so its representative instant is h − 0.5: record 13 describes 12:30.
//
// Missing values: the data dictionary marks a value missing when it is at or above a per-field code (9999 for
// radiation, 999900 for illuminance, 99.9 for temperature ...); such values, and empty fields, are
// std::nullopt here.
#pragma once

#include "sunsky/civil_time.h"

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace fly::sunsky {

// The LOCATION header line.
struct EpwLocation {
  std::string city;
  std::string stateProvinceRegion;
  std::string country;
  std::string source;          // e.g. "IWEC", "TMY3", "ISD-TMYx"
  std::string wmo;             // WMO station number, text as in the file (usually 6 digits)
  double latitudeDeg = 0.0;    // [−90, 90], north positive
  double longitudeDeg = 0.0;   // [−180, 180], east positive
  double timeZoneHours = 0.0;  // standard time − UTC, hours, [−12, 14]
  double elevationM = 0.0;     // metres above sea level, [−1000, 9999.9)
};

// One hourly record. Radiation fields are Wh/m² summed over the record's hour, which equals the hour's mean
// irradiance in W/m² (hence the names *Wm2); illuminances are the hour's mean in lux.
struct EpwRecord {
  int lineNumber = 0;  // 1-based line in the file, for messages
  int year = 0;        // not used: typical-year files mix years month by month
  int month = 1;       // 1..12
  int day = 1;         // 1..31 (29 February only in files that keep leap days)
  int hour = 1;        // 1..24, the END of the hour [hour − 1, hour) local standard time
  int minute = 0;      // 0..60 as written (60 in TMY2/IWEC-derived files, 0 in TMY3-derived ones); unused
  std::string dataSourceFlags;

  std::optional<double> dryBulbC;                         // °C
  std::optional<double> dewPointC;                        // °C
  std::optional<double> relativeHumidityPct;              // %
  std::optional<double> pressurePa;                       // station pressure, Pa
  std::optional<double> extraterrestrialHorizontalWm2;    // W/m² (Wh/m² in the hour)
  std::optional<double> extraterrestrialDirectNormalWm2;  // W/m²
  std::optional<double> horizontalInfraredWm2;            // W/m²
  std::optional<double> ghiWm2;                           // global horizontal irradiance, W/m², ≥ 0
  std::optional<double> dniWm2;                           // direct normal irradiance, W/m², ≥ 0
  std::optional<double> dhiWm2;                           // diffuse horizontal irradiance, W/m², ≥ 0
  std::optional<double> ghiLux;                           // global horizontal illuminance, lux, ≥ 0
  std::optional<double> dniLux;                           // direct normal illuminance, lux, ≥ 0
  std::optional<double> dhiLux;                           // diffuse horizontal illuminance, lux, ≥ 0
  std::optional<double> zenithLuminanceCdM2;              // cd/m², ≥ 0
  std::optional<double> windDirectionDeg;                 // clockwise from north, 0..360
  std::optional<double> windSpeedMS;                      // m/s
  std::optional<double> totalSkyCoverTenths;              // 0..10
  std::optional<double> opaqueSkyCoverTenths;             // 0..10
  std::optional<double> visibilityKm;
  std::optional<double> ceilingHeightM;             // 77777 = unlimited, 88888 = cirroform
  std::optional<double> presentWeatherObservation;  // 0 = observed; 9 (missing) = not observed
  std::string presentWeatherCodes;                  // 9 digits, TMY2 convention, as written
  std::optional<double> precipitableWaterMm;
  std::optional<double> aerosolOpticalDepth;  // broadband, dimensionless (e.g. 0.12)
  std::optional<double> snowDepthCm;
  std::optional<double> daysSinceLastSnowfall;
  std::optional<double> albedo;  // ground reflectance, 0..1
  std::optional<double> liquidPrecipitationDepthMm;
  std::optional<double> liquidPrecipitationQuantityH;  // hours the depth was collected over

  // The instant the record describes: the middle of its hour, local standard time, in hours of its day.
  double representativeHour() const { return hour - 0.5; }
};

struct EpwFile {
  std::string fileName;  // as given to parseEpw / loadEpw, for messages
  EpwLocation location;
  std::vector<EpwRecord> records;  // consecutive hours in file order
  bool hasLeapDay = false;         // a record falls on 29 February
};

// Parses EPW text. Throws InputError with `fileName`, the line and column, the field's name and a hint for:
// an empty or binary file, a missing or misplaced header line, a LOCATION value out of range (latitude 91), a
// record with the wrong number of fields or a field that is not a number, a date or hour out of range (month
// 13, hour 25), a negative radiation or illuminance, hours out of order or missing, more than one year, more
// than one record per hour, a file that ends in the middle of a line or before its DATA PERIODS end.
EpwFile parseEpw(std::string_view text, const std::string& fileName);

// Reads and parses a file; a missing, unreadable or 0-byte file is an InputError too.
EpwFile loadEpw(const std::filesystem::path& path);

// The weather at one local-standard-time instant, interpolated from the hourly records.
struct EpwSample {
  // The records interpolated: value = (1 − weightAfter)·records[recordBefore] +
  // weightAfter·records[recordAfter]. weightAfter is 0 exactly at a record's mid-point (then recordAfter ==
  // recordBefore).
  std::size_t recordBefore = 0;
  std::size_t recordAfter = 0;
  double weightAfter = 0.0;

  std::optional<double> dryBulbC;
  std::optional<double> dewPointC;
  std::optional<double> pressurePa;
  std::optional<double> ghiWm2;
  std::optional<double> dniWm2;
  std::optional<double> dhiWm2;
  std::optional<double> ghiLux;
  std::optional<double> dniLux;
  std::optional<double> dhiLux;
  std::optional<double> zenithLuminanceCdM2;
  std::optional<double> albedo;
};

// The weather on `month`/`day` at `localStandardHour` ∈ [0, 24] (local STANDARD time: subtract an hour from
// daylight-saving clock time; from UTC, add EpwLocation::timeZoneHours). Each value is linearly interpolated
// between the mid-points of the two records around the instant: at 12:30 exactly record 13, at 13:00 the mean
// of records 13 and 14, at 0:10 between the previous day's record 24 and record 1. A full-year file wraps
// from 31 December to 1 January; a part-year file gives its first (last) record for the first (last) half
// hour it covers. A value missing in either record used is missing in the sample. At night the records hold 0
// radiation and illuminance, so the sample is 0 too. Near sunrise and sunset the hour's mean may be non-zero
// while the sun is below the horizon at the sampled instant (or 0 while it is just above): pair the sample
// with the sun's position at the same instant, and take no direct light from a sun below the horizon. Throws
// InputError naming the file for a date the file does not cover or that does not exist (month 13, 30
// February, 29 February in a file without leap day) and for an hour outside [0, 24].
EpwSample sampleAt(const EpwFile& file, int month, int day, double localStandardHour);

// The sample at a UTC instant: shifted to the file's standard time (LOCATION time zone), then sampleAt.
EpwSample sampleAtUtc(const EpwFile& file, const UtcTime& utc);

}  // namespace fly::sunsky
