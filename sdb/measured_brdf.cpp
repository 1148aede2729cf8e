#include "sdb/measured_brdf.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <utility>

#include "base/error.h"
#include "base/file_io.h"

namespace fly::sdb {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr const char* kChannelNames[3] = {"red", "green", "blue"};

InputError merlError(const std::filesystem::path& file, const std::string& message, std::string hint = {}) {
  return InputError(SourceLocation{file.string()}, message, std::move(hint));
}

std::string str(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

}  // namespace

MeasuredBrdf readMerlBrdf(const std::filesystem::path& file) {
  const std::string bytes = readInputFile(file, "measured BRDF file");
  constexpr size_t kHeader = 3 * sizeof(int32_t);
  if (bytes.size() < kHeader) {
    throw merlError(file, "is " + std::to_string(bytes.size()) +
                              " bytes long, too short for a MERL BRDF header (three 32-bit dimensions)",
                    "give a MERL binary BRDF file (.binary), 90 × 90 × 180 samples of 3 channels");
  }
  std::array<int32_t, 3> dims{};
  std::memcpy(dims.data(), bytes.data(), kHeader);
  if (dims[0] != MeasuredBrdf::kThetaHalfRes || dims[1] != MeasuredBrdf::kThetaDiffRes ||
      dims[2] != MeasuredBrdf::kPhiDiffRes) {
    throw merlError(file,
                    "declares " + std::to_string(dims[0]) + " × " + std::to_string(dims[1]) + " × " +
                        std::to_string(dims[2]) +
                        " samples; a MERL isotropic BRDF has 90 (θh) × 90 (θd) × 180 (φd)",
                    "fly reads the MERL database's isotropic format only; resample the table to it");
  }
  const size_t expected = kHeader + 3 * MeasuredBrdf::kSamples * sizeof(double);
  if (bytes.size() != expected) {
    throw merlError(file, "is " + std::to_string(bytes.size()) + " bytes long; 90 × 90 × 180 samples of 3 channels take " +
                              std::to_string(expected) + (bytes.size() < expected ? " (the file is cut off)" : ""),
                    "copy the file again; a MERL file is the header and 3 · 1 458 000 doubles");
  }
  std::vector<Rgb> samples(MeasuredBrdf::kSamples);
  const std::vector<uint8_t>& valid = MeasuredBrdf::validSamples();
  for (int ch = 0; ch < 3; ++ch) {
    const char* base = bytes.data() + kHeader + size_t(ch) * MeasuredBrdf::kSamples * sizeof(double);
    for (size_t s = 0; s < MeasuredBrdf::kSamples; ++s) {
      double v;
      std::memcpy(&v, base + s * sizeof(double), sizeof v);
      // Samples whose directions lie below the surface were never measured; a table may hold negative markers
      // there (MERL's reference reader reports negative values as "Below horizon"), which read as 0.
      if (!std::isfinite(v) || (v < 0.0 && valid[s])) {
        const int i = int(s / (MeasuredBrdf::kThetaDiffRes * MeasuredBrdf::kPhiDiffRes));
        const int j = int(s / MeasuredBrdf::kPhiDiffRes % MeasuredBrdf::kThetaDiffRes);
        const int k = int(s % MeasuredBrdf::kPhiDiffRes);
        const HalfDiffAngles a = MeasuredBrdf::sampleAngles(i, j, k);
        constexpr double kDeg = 180.0 / kPi;
        throw merlError(file,
                        std::string("its ") + kChannelNames[ch] + " sample at θh = " + str(a.thetaHalfRad * kDeg) +
                            "°, θd = " + str(a.thetaDiffRad * kDeg) + "°, φd = " + str(a.phiDiffRad * kDeg) +
                            "° (index " + std::to_string(i) + ", " + std::to_string(j) + ", " + std::to_string(k) +
                            ") is " + (std::isnan(v) ? std::string("NaN") : str(v)) +
                            "; a BRDF is finite and ≥ 0",
                        "repair the table (e.g. set missing samples to those of their neighbours) and save it again");
      }
      samples[s][ch] = v < 0.0 ? 0.0f : float(v * kMerlChannelScale[ch]);
    }
  }
  return MeasuredBrdf(std::move(samples));
}

void writeMerlBrdf(const std::filesystem::path& file, const std::function<Rgb(const HalfDiffAngles&)>& brdfPerSr) {
  std::vector<double> values(3 * MeasuredBrdf::kSamples);
  for (int i = 0; i < MeasuredBrdf::kThetaHalfRes; ++i) {
    for (int j = 0; j < MeasuredBrdf::kThetaDiffRes; ++j) {
      for (int k = 0; k < MeasuredBrdf::kPhiDiffRes; ++k) {
        const Rgb f = brdfPerSr(MeasuredBrdf::sampleAngles(i, j, k));
        const size_t s = MeasuredBrdf::sampleIndex(i, j, k);
        for (int ch = 0; ch < 3; ++ch) {
          values[size_t(ch) * MeasuredBrdf::kSamples + s] = double(f[ch]) / kMerlChannelScale[ch];
        }
      }
    }
  }
  const std::array<int32_t, 3> dims = {MeasuredBrdf::kThetaHalfRes, MeasuredBrdf::kThetaDiffRes,
                                       MeasuredBrdf::kPhiDiffRes};
  std::string bytes(sizeof dims + values.size() * sizeof(double), '\0');
  std::memcpy(bytes.data(), dims.data(), sizeof dims);
  std::memcpy(bytes.data() + sizeof dims, values.data(), values.size() * sizeof(double));
  writeFileAtomic(file, bytes);
}

}  // namespace fly::sdb
