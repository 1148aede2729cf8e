#include "sunsky/sky_matrix.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <string>
#include <thread>

#include "base/error.h"

namespace fly::sunsky {

namespace {

// PerezSkyInput's dew point when a record has none (10 °C: W = 1.87 cm; gendaymtx assumes 11 °C).
constexpr double kDefaultDewPointC = 10.0;

[[noreturn]] void throwAtRecord(const EpwFile& file, const EpwRecord& r, const std::string& message,
                                const std::string& hint) {
  throw InputError({file.fileName, r.lineNumber, 0, {}}, message, hint);
}

double requiredRadiation(const EpwFile& file, const EpwRecord& r, const std::optional<double>& value,
                         const char* name) {
  if (!value) {
    throwAtRecord(
        file, r,
        std::string(name) + " is missing on " + std::to_string(r.month) + "/" + std::to_string(r.day) +
            " hour " + std::to_string(r.hour),
        "annual daylight needs every hour's direct normal and diffuse horizontal irradiance: fill the "
        "gap in the weather file (e.g. from a neighbouring hour) or use a complete file");
  }
  return *value;
}

}  // namespace

WeatherHour weatherHour(const EpwFile& file, std::size_t record) {
  if (record >= file.records.size()) {
    throw std::out_of_range("weatherHour: record " + std::to_string(record) + " of " +
                            std::to_string(file.records.size()));
  }
  const EpwRecord& r = file.records[record];
  const double directNormalWm2 = requiredRadiation(file, r, r.dniWm2, "direct normal irradiance");
  const double diffuseHorizontalWm2 = requiredRadiation(file, r, r.dhiWm2, "diffuse horizontal irradiance");

  WeatherHour h;
  h.record = record;
  h.localStandardHour = r.representativeHour();
  const UtcTime midnight{
      file.hasLeapDay ? kSolarYearWithLeapDay : kSolarYearWithoutLeapDay, r.month, r.day, 0, 0, 0.0};
  h.dayOfYear = dayOfYear(midnight);
  SpaInput spa;
  spa.utc = addHours(midnight, h.localStandardHour - file.location.timeZoneHours);
  spa.latitudeDeg = file.location.latitudeDeg;
  spa.longitudeDeg = file.location.longitudeDeg;
  // The elevation only sets the standard-atmosphere refraction; SPA takes −500 m to 11 km, EPW −1 km to 10
  // km.
  spa.elevationM = std::clamp(file.location.elevationM, -500.0, 11000.0);
  h.sun = sunPosition(spa);
  if (!(diffuseHorizontalWm2 > 0.0)) return h;

  PerezSkyInput in;
  in.sunZenithDeg = h.sun.apparentZenithDeg;
  in.sunAzimuthDeg = h.sun.azimuthDeg;
  in.units = PerezSkyInput::Units::kIrradianceWm2;
  in.directNormal = directNormalWm2;
  in.diffuseHorizontal = diffuseHorizontalWm2;
  in.dayOfYear = h.dayOfYear;
  in.dewPointC = std::clamp(r.dewPointC.value_or(kDefaultDewPointC), -90.0, 60.0);
  try {
    h.sky = makePerezSky(in);
  } catch (const InputError& e) {
    throwAtRecord(file, r, e.message(), e.hint());
  }

  SunDiscInput disc;
  disc.zenithDeg = h.sun.apparentZenithDeg;
  disc.azimuthDeg = h.sun.azimuthDeg;
  disc.turbidity = kWeatherSunTurbidity;
  disc.pressureHpa = std::clamp(r.pressurePa.value_or(101325.0) / 100.0, 300.0, 1100.0);
  disc.dayOfYear = h.dayOfYear;
  // Perez's direct efficacy reaches 127 lm/W (bin 1, Δ = 0.6): bounded by the extraterrestrial illuminance.
  const double limitLux = kLuminousSolarConstantLux * eccentricityCorrection(h.dayOfYear);
  h.sunDisc = sunDiscWithIlluminance(disc, std::min(h.sky->directNormalLux(), limitLux));
  return h;
}

SkyMatrix makeSkyMatrix(const EpwFile& file, const SkyMatrixOptions& options) {
  SkyMatrix m{makeSkyPatches(options.multiplier)};
  checkInputRange("threads", options.threads, 0, 1024, "", "give 0 for one per processor, or a count");
  m.sunPlacement = options.vector.sun;
  const std::size_t patchCount = static_cast<std::size_t>(m.patches.count());
  m.radianceCdM2.assign(file.records.size() * patchCount, Rgb(0.0f));
  m.hours.resize(file.records.size());

  auto computeRow = [&](std::size_t k) {
    const EpwRecord& r = file.records[k];
    SkyMatrixHour& info = m.hours[k];
    info.month = r.month;
    info.day = r.day;
    info.hour = r.hour;
    const WeatherHour h = weatherHour(file, k);
    info.sunDirEnu = sunDirectionEnu(h.sun.apparentZenithDeg, h.sun.azimuthDeg);
    if (!h.sky) return;
    info.diffuseHorizontalLux = h.sky->diffuseHorizontalLux();
    info.sunNormalIlluminanceLux = luminance(h.sunDisc.normalIlluminanceLux);
    const SkyVector v = makeSkyVector(*h.sky, h.sunDisc, m.patches, options.vector);
    info.sunPatch = v.sunPatch;
    Rgb* row = m.radianceCdM2.data() + k * patchCount;
    for (std::size_t p = 0; p < patchCount; ++p) row[p] = Rgb(v.radianceCdM2[p]);
  };

  // Rows are independent: threads take records in turn. An error is reported for the first record that has
  // one, as a serial loop would.
  const std::size_t threadCount = std::min<std::size_t>(
      options.threads > 0 ? options.threads : std::max(1u, std::thread::hardware_concurrency()),
      std::max<std::size_t>(1, file.records.size()));
  std::atomic<std::size_t> next{0};
  std::vector<std::exception_ptr> errors(file.records.size());
  std::atomic<std::size_t> firstError{file.records.size()};
  auto work = [&] {
    for (std::size_t k = next++; k < file.records.size() && k < firstError; k = next++) {
      try {
        computeRow(k);
      } catch (...) {
        errors[k] = std::current_exception();
        std::size_t seen = firstError;
        while (k < seen && !firstError.compare_exchange_weak(seen, k)) {
        }
      }
    }
  };
  std::vector<std::thread> threads;
  for (std::size_t t = 1; t < threadCount; ++t) threads.emplace_back(work);
  work();
  for (std::thread& t : threads) t.join();
  if (firstError < file.records.size()) std::rethrow_exception(errors[firstError]);
  return m;
}

}  // namespace fly::sunsky
