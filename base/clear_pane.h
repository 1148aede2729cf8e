// The transmittance of clear glass (sdb::Material::hasClearTransmission): a thin-walled pane that light
// crosses straight, which the SDB and both engines share (the GL engine's copy: raster/shaders/scene_glsl.h,
// kGlassPane).
//
// The pane is a slab of index n with two parallel faces and absorption inside. Per polarisation (s, p), with
// R the reflectance of one air–glass face at θ (the Fresnel equations), θt from Snell's law and
// τ = τ0^(1 / cos θt) the internal transmittance along the slanted path, the light that crosses after any
// number of internal reflections is (Born and Wolf, "Principles of Optics"; Tregenza and Sharples,
// "Daylighting algorithms", algorithm 2.34)
//   T_pol = (1 − R)² τ / (1 − R² τ²),   S(θ) = (T_s + T_p) / 2.
// A material fixes the pane's transmittance at normal incidence, T_n = t (1 − R0) per channel (the energy
// rule of sdb/material.h at cos θ = 1: t the transmission colour, R(θ) = R0 + (R90 − R0)(1 − cos θ)⁵ the
// rule's reflect input, R0 = r F0 and R90 = r for reflection colour r, F0 = ((n − 1)/(n + 1))² from its ior;
// a metalness mix keeps that form). τ0 solves S(0) = T_n: with R0 = F0, T_n (1 − R0² τ0²) = (1 − R0)² τ0, whose positive root is
// τ0 = 2 T_n / ((1 − R0)² + √((1 − R0)⁴ + 4 T_n² R0²)), clamped to [0, 1]. Where T_n exceeds the lossless
// slab's (1 − R0)/(1 + R0) (a pane with little reflection colour), τ0 = 1 and the lossless slab's shape is
// scaled to T_n. So
//   T(θ) = min(T_n S(θ) / S(0), t (1 − R(θ))),
// never above the energy rule's one-interface transmittance at that angle (Schlick's approximation),
// so that with the rule's reflected and diffuse shares nothing sends out more than it receives. For indices
// of 1.2 to 2.2 (every glass) the slab lies below that bound at every angle; the bound caps it only outside
// that range, where Schlick's F departs from Fresnel's. Uniform (non-Fresnel) reflection has no index: there
// T(θ) = t (1 − r) at every angle.
#pragma once

#include "base/color.h"

namespace fly {

// τ0 of a slab whose faces reflect r0 at normal incidence and whose transmittance at normal incidence is
// normalT (both in [0, 1]), in [0, 1].
float slabInternalTransmittance(float r0, float normalT);

// S(θ) at |cos θ| = cosTheta for a slab of index n ≥ 1 with internal transmittance tau0 at normal incidence.
float slabTransmittance(float cosTheta, float n, float tau0);

class ClearPane {
 public:
  ClearPane() = default;
  // f0: Schlick's F0 = ((n − 1)/(n + 1))² of the material's ior, which sets the slab's index, < 0 for uniform
  // reflection (no index: T = t (1 − R0) at every angle); t the transmission colour, R0 and R90 the energy
  // rule's reflect input at normal and grazing incidence (each clamped to [0, 1]).
  ClearPane(float f0, const Rgb& transmission, const Rgb& r0, const Rgb& r90);
  // The same for a reflection colour r: R0 = r F0 and R90 = r (uniform reflection: R0 = R90 = r).
  ClearPane(float f0, const Rgb& transmission, const Rgb& reflection)
      : ClearPane(f0, transmission, reflection * (f0 >= 0.0f ? f0 : 1.0f), reflection) {}

  // T(θ) per channel at cos θ = cosTheta, from either face (|cos θ| is used); finite and in [0, 1].
  Rgb at(float cosTheta) const;
  // T_n = T(0).
  const Rgb& normalTransmittance() const { return normalT_; }

 private:
  bool fresnel_ = false;
  float f0_ = 0.0f;
  float n_ = 1.0f;
  Rgb t_{0.0f};
  Rgb r0_{0.0f};
  Rgb r90_{0.0f};
  Rgb normalT_{0.0f};
  Rgb tau0_{0.0f};
  Rgb scale_{0.0f};  // T_n / S(0)
};

}  // namespace fly
