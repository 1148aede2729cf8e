// Lights in photometric units (glTF KHR_lights_punctual): point and spot in candela, directional in lux,
// goniometric from IES LM-63 files. Emissive surfaces are materials (Material::emissionLuminance, cd/m²).
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
  // Point, spot: luminous intensity in cd, ≥ 0. Directional: illuminance in lux on a surface facing the light,
  // ≥ 0. Goniometric: a dimensionless multiplier of the IES candela table, ≥ 0 (default 1).
  float intensity = 1.0f;
  // Distance in metres beyond which the light is cut off with KHR_lights_punctual's recommended smooth window
  // (1 − (d/range)⁴)²; ∞ (default) = inverse square law only. Not for directional lights.
  float rangeM = std::numeric_limits<float>::infinity();
  // Spot cone, radians: full intensity inside `innerConeRad`, zero outside `outerConeRad`, blended between
  // (KHR_lights_punctual). 0 ≤ inner < outer ≤ π/2. Defaults 0 and π/4 (glTF).
  float innerConeRad = 0.0f;
  float outerConeRad = 0.7853982f;
  // Goniometric lights: the measured distribution and where it came from.
  std::shared_ptr<const IesProfile> ies;
  std::string iesPath;
};

// Checks each parameter's range; returns "" when valid, otherwise a sentence naming the bad parameter.
std::string validate(const Light& l);

}  // namespace fly::sdb
