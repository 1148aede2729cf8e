// Measured-BRDF tables for tests and benchmarks, made in memory from an analytic BRDF so that no MERL file
// (35 MB each) is needed: every sample (i, j, k) is the BRDF at its own half/difference angles.
#pragma once

#include <memory>
#include <vector>

#include "sdb/car_paint_brdf.h"
#include "sdb/measured_brdf.h"

namespace fly::test {

// The MERL table of `paint` (0 where a sample's directions lie below the surface).
inline std::shared_ptr<const sdb::MeasuredBrdf> tableOf(const sdb::CarPaintBrdf& paint) {
  std::vector<Rgb> samples(sdb::MeasuredBrdf::kSamples);
  for (int i = 0; i < sdb::MeasuredBrdf::kThetaHalfRes; ++i) {
    for (int j = 0; j < sdb::MeasuredBrdf::kThetaDiffRes; ++j) {
      for (int k = 0; k < sdb::MeasuredBrdf::kPhiDiffRes; ++k) {
        vec3 wi, wo;
        sdb::directionsOf(sdb::MeasuredBrdf::sampleAngles(i, j, k), wi, wo);
        samples[sdb::MeasuredBrdf::sampleIndex(i, j, k)] = paint.evalPerSr(wi, wo);
      }
    }
  }
  return std::make_shared<const sdb::MeasuredBrdf>(std::move(samples));
}

}  // namespace fly::test
