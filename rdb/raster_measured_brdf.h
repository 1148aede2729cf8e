// A measured or fitted BRDF (sdb/measured_brdf.h, sdb/car_paint_brdf.h) lowered for the OpenGL engine's ball
// textures (raster/ball_texture.h; FLY §4) as plain data: the MERL table as floats for a 3D texture, or the
// car-paint model's parameters, plus the directional albedo and where the material's objects stand. The
// engine evaluates the same BRDF in GLSL from this data and never includes sdb/.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "base/color.h"
#include "base/math.h"

namespace fly::sdb {
struct Material;
}  // namespace fly::sdb

namespace fly::rdb {

enum class RasterBrdfKind : uint32_t { kTable = 0, kCarPaint = 1 };

// The car-paint model of sdb::CarPaintBrdf, its parameters as given (units and ranges there), and the coat's
// internal diffuse reflectance F̄int(η) (sdb::internalDiffuseReflectance), which the shader does not integrate.
struct RasterCarPaint {
  Rgb baseAlbedo{0.0f};
  std::array<Rgb, 3> lobeF0{Rgb(0.0f), Rgb(0.0f), Rgb(0.0f)};  // 0 = no lobe
  std::array<float, 3> lobeAlpha{0.3f, 0.3f, 0.3f};
  float coatIor = 1.5f;
  float coatAlpha = 0.02f;
  float internalDiffuseReflectance = 0.0f;

  bool operator==(const RasterCarPaint&) const = default;
};

// Directional albedo samples: ρ(θo) at cos θo = (k + 0.5) / kRasterAlbedoSteps, k = 0 … kRasterAlbedoSteps − 1.
inline constexpr uint32_t kRasterAlbedoSteps = 32;

struct RasterMeasuredBrdf {
  RasterBrdfKind kind = RasterBrdfKind::kCarPaint;
  // kTable: the MERL table (sdb::MeasuredBrdf) as RGBA floats in its own order [θh][θd][φd] (φd fastest),
  // rgb the BRDF in 1/sr, a = 1 where the sample's directions both lie above the surface
  // (sdb::MeasuredBrdf::validSamples), else 0 — the evaluation leaves those corners out, as sdb's does.
  // Empty for kCarPaint.
  std::vector<float> tableRgba;
  RasterCarPaint carPaint;  // kCarPaint
  // ρ(θo) = ∫ f(ωi, ωo) cos θi dωi per channel (kRasterAlbedoSteps values), by quadrature over the half vector
  // (raster_measured_brdf.cpp, directionalAlbedo): the ball texture's environment term scales its
  // BRDF-weighted mean of the sky by it (raster/ball_texture.h).
  std::vector<Rgb> albedo;
  // The objects of this material: the centre and radius (m) of their bounding box. The ball texture sees
  // point, spot and goniometric lights as distant lights from this centre.
  vec3 centreM{0.0f};
  float radiusM = 0.0f;
  uint32_t sdbMaterialId = 0;

  bool operator==(const RasterMeasuredBrdf&) const = default;
};

// The measured BRDF of `m` (m.isMeasured()) as plain data, with its albedo table; centreM and radiusM are left
// for the caller (they depend on the geometry).
RasterMeasuredBrdf lowerMeasuredBrdf(const sdb::Material& m, uint32_t sdbMaterialId);

}  // namespace fly::rdb
