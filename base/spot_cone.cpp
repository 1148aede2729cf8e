#include "base/spot_cone.h"

#include "base/math.h"

namespace fly {

double spotConeSolidAngleSr(double cosInner, double cosOuter) {
  const double d = std::max(static_cast<double>(kSpotMinCosWidth), cosInner - cosOuter);
  const double u = std::min(1.0, cosOuter + d);
  const double ramp = u - cosOuter;
  return 2.0 * kPi * ((1.0 - u) + ramp * ramp * ramp / (3.0 * d * d));
}

}  // namespace fly
