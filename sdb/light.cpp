#include "sdb/light.h"

#include <cmath>

#include "base/blackbody.h"
#include "base/spot_cone.h"

namespace fly::sdb {

const char* lightTypeName(LightType t) {
  switch (t) {
    case LightType::kPoint: return "point";
    case LightType::kSpot: return "spot";
    case LightType::kDirectional: return "directional";
    case LightType::kGoniometric: return "goniometric";
  }
  return "unknown";
}

double fluxPerUnitIntensityLm(const Light& l) {
  switch (l.type) {
    case LightType::kPoint: return 4.0 * kPi;
    case LightType::kSpot: return spotConeSolidAngleSr(std::cos(l.innerConeRad), std::cos(l.outerConeRad));
    case LightType::kGoniometric: return l.ies ? l.ies->totalFluxLm() : 0.0;
    case LightType::kDirectional: return 0.0;
  }
  return 0.0;
}

double luminousFluxLm(const Light& l) {
  return static_cast<double>(luminance(l.color)) * l.intensity * fluxPerUnitIntensityLm(l);
}

std::string validate(const Light& l) {
  if (!(isFinite(l.color) && l.color.r >= 0.0f && l.color.g >= 0.0f && l.color.b >= 0.0f)) {
    return "color must be finite and ≥ 0 per channel";
  }
  if (l.temperatureK != 0.0f &&
      !(l.temperatureK >= kMinColourTemperatureK && l.temperatureK <= kMaxColourTemperatureK)) {
    return "colour temperature must be in [1000, 40000] K";
  }
  if (!(std::isfinite(l.intensity) && l.intensity >= 0.0f)) return "intensity must be finite and ≥ 0";
  if (!(l.rangeM > 0.0f)) return "range must be > 0 metres (or ∞)";
  if (l.type == LightType::kSpot &&
      !(l.innerConeRad >= 0.0f && l.innerConeRad < l.outerConeRad && l.outerConeRad <= kPiF / 2.0f)) {
    return "spot cone angles must satisfy 0 ≤ inner < outer ≤ 90°";
  }
  if (l.type == LightType::kGoniometric && !l.ies) return "a goniometric light needs an IES profile";
  return "";
}

}  // namespace fly::sdb
