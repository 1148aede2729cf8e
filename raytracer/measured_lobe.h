// A measured BRDF as the Bsdf uses it (raytracer/bsdf.h): a tabulated one (raytracer/tabulated_lobe.h) or the
// compact car-paint model (raytracer/car_paint_lobe.h), built once per table or material by the integrator
// and shared by the Bsdfs of its material. Directions are local to the shading frame: +z the normal on the
// side of ωo (towards the sensor), ωi towards the light, both unit.
#pragma once

#include "base/color.h"
#include "base/math.h"

namespace fly::raytracer {

class MeasuredLobe {
 public:
  virtual ~MeasuredLobe() = default;

  // f(ωo, ωi) in 1/sr; 0 unless both lie above the surface.
  virtual Rgb eval(const vec3& wo, const vec3& wi) const = 0;
  // The density per steradian with which sample() draws ωi. Its integral over the sphere is at most 1: the
  // rest is the probability that sample() returns false.
  virtual float pdf(const vec3& wo, const vec3& wi) const = 0;
  // A direction ωi with density pdf() (wo.z > 0): uChoice ∈ [0, 1) chooses among the lobe's sampling
  // strategies, u ∈ [0, 1)² the direction. False when the draw leaves no direction above the surface.
  virtual bool sample(const vec3& wo, float uChoice, const vec2& u, vec3& wi) const = 0;
  // An estimate of the directional albedo ∫ f cos θi dωi for light leaving at cos θo = cosO, per channel:
  // Russian roulette's survival and the lobe choice against partial coverage use it.
  virtual Rgb albedo(float cosO) const = 0;
};

}  // namespace fly::raytracer
