// The cone of a spot light as KHR_lights_punctual recommends it: full intensity inside the inner cone, none
// outside the outer cone, and between them the square of a linear ramp in the cosine of the angle from the
// axis. The baker (raytracer/) and the GL engine's light evaluation (rdb/) use this function, and a light's
// luminous flux is its intensity times the cone's weighted solid angle below.
#pragma once

#include <algorithm>

namespace fly {

// The ramp's smallest width in cos θ, KHR_lights_punctual's max(0.001, cos inner − cos outer): a hard-edged
// cone (inner = outer) still fades over a sliver.
inline constexpr float kSpotMinCosWidth = 0.001f;

// The factor in [0, 1] that multiplies a spot light's intensity at `cosAngle` = cos θ from its axis:
// t = clamp((cos θ − cos outer) / max(0.001, cos inner − cos outer), 0, 1), squared.
inline float spotConeAttenuation(float cosAngle, float cosInner, float cosOuter) {
  const float t =
      std::clamp((cosAngle - cosOuter) / std::max(kSpotMinCosWidth, cosInner - cosOuter), 0.0f, 1.0f);
  return t * t;
}

// ∫ spotConeAttenuation dω over the sphere, in steradians: the luminous flux in lm of a spot of 1 cd.
// With μ = cos θ, d = max(0.001, cos inner − cos outer) and u = min(1, cos outer + d) (where the ramp reaches
// 1, or the axis): Ω = 2π [(1 − u) + (u − cos outer)³ / (3 d²)]; for inner < outer this is
// 2π [(1 − cos inner) + (cos inner − cos outer) / 3].
double spotConeSolidAngleSr(double cosInner, double cosOuter);

}  // namespace fly
