// Fitting the compact car-paint BRDF (base/car_paint.h: a clear coat over GGX metallic flakes and a diffuse
// base) to a measured table.
#pragma once

#include "base/car_paint.h"
#include "sdb/measured_brdf.h"

namespace fly::sdb {

// The model and its Fresnel terms are base's (base/car_paint.h); the SDB adds the fit.
using fly::CarPaintBrdf;
using fly::CarPaintLobe;
using fly::dielectricFresnel;
using fly::internalDiffuseReflectance;

// The fitted model and how well it matches the table it was fitted to.
struct CarPaintFit {
  CarPaintBrdf brdf;
  // Over the table's measured samples (MeasuredBrdf::validSamples) with θi and θo below 80°: the RMS over
  // samples and channels of (f_fit − f_table) / (f_table + 1/π · 0.01), a relative error that does not blow
  // up where the table is near 0; and the same weighted by cos θi cos θo, which is what reflected light sees.
  float rmsRelativeError = 0.0f;
  float rmsRelativeErrorCosWeighted = 0.0f;
  int iterations = 0;
};

// Fits the model with `lobes` flake lobes (1..kMaxLobes) and the given coat index to a measured table by
// Levenberg–Marquardt on log(f + ε) over a fixed subset of its samples, from a start that the table's own
// values suggest (its value at the mirror direction for the coat, its values far from it for ρd).
CarPaintFit fitCarPaint(const MeasuredBrdf& table, int lobes = 2, float coatIor = 1.5f);

}  // namespace fly::sdb
