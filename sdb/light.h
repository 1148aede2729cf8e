// Lights in photometric units (glTF KHR_lights_punctual): point and spot in candela, directional in lux,
// goniometric from IES LM-63 or EULUMDAT files. Emissive surfaces are materials (Material::emissionLuminance, cd/m²).
// Lights shine along their node's local −Z; a goniometric light's photometric axis (γ = 0, nadir) is local −Z
// and its C = 0° half-plane contains local +X.
#pragma once

#include <limits>
#include <memory>
#include <string>

#include "base/color.h"
#include "sdb/ies.h"

namespace fly::sdb {

enum class LightType { kPoint, kSpot, kDirectional, kGoniometric };

const char* lightTypeName(LightType t);  // "point", "spot", "directional", "goniometric"

struct Light {
  std::string name;
  LightType type = LightType::kPoint;
  // Linear Rec.709 tint, each channel ≥ 0; default white. The emitted photometric RGB is color × intensity, as
  // glTF defines it.
  Rgb color{1.0f};
  // The correlated colour temperature in K that `color` was made from (planckianRec709, luminance 1), in
  // [1000, 40000]; 0 when the colour was given as RGB. Kept for reports: `color` is what lights the scene.
  float temperatureK = 0.0f;
  // Point, spot: luminous intensity in cd, ≥ 0. Directional: illuminance in lux on a surface facing the light,
  // ≥ 0. Goniometric: a dimensionless multiplier of the IES candela table, ≥ 0 (default 1).
  float intensity = 1.0f;
  // Distance in metres beyond which the light is cut off with KHR_lights_punctual's recommended smooth window
  // clamp(1 − (d/range)⁴, 0, 1), as the baker applies it; ∞ (default) = inverse square law only. Not for directional lights.
  float rangeM = std::numeric_limits<float>::infinity();
  // Spot cone, radians: full intensity inside `innerConeRad`, zero outside `outerConeRad`, blended between
  // (KHR_lights_punctual). 0 ≤ inner < outer ≤ π/2. Defaults 0 and π/4 (glTF).
  float innerConeRad = 0.0f;
  float outerConeRad = 0.7853982f;
  // Goniometric lights: the measured distribution and where it came from.
  std::shared_ptr<const IesProfile> ies;
  std::string iesPath;
};

// Luminous flux in lm that a light of intensity 1 and white colour emits: 4π for a point light, the cone's
// weighted solid angle for a spot light (base/spot_cone.h, KHR_lights_punctual's falloff), the profile's
// integrated flux (IesProfile::totalFluxLm) for a goniometric light; 0 for a directional light, whose flux is
// not finite.
double fluxPerUnitIntensityLm(const Light& l);

// The luminous flux in lm the light emits: luminance(color) × intensity × fluxPerUnitIntensityLm; 0 for a
// directional light.
double luminousFluxLm(const Light& l);

// Checks each parameter's range; returns "" when valid, otherwise a sentence naming the bad parameter.
std::string validate(const Light& l);

}  // namespace fly::sdb
