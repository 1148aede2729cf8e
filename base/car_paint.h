// A compact car-paint BRDF: a smooth-to-glossy clear coat over a pigmented base with metallic flakes, the
// model family that Günther, Chen, Goesele, Wald and Seidel fitted to measured car paints ("Efficient
// Acquisition and Realistic Rendering of Car Paint", VMV 2005: a diffuse term and a few Cook–Torrance lobes
// under a clear coat), with GGX lobes (Walter et al. 2007) as elsewhere in fly, and the coat as a dielectric
// layer in the manner of Weidlich and Wilkie ("Arbitrarily Layered Micro-Facet Surfaces", GRAPHITE 2007):
//
//   f(ωi, ωo) = F(θd; η) D(θh; αc) G(ωi, ωo; αc) / (4 cos θi cos θo)                 the coat's reflection
//             + (1 − F(θi; η)) (1 − F(θo; η)) / η² · f_base(ωi', ωo')                  the base through it
//   f_base    = ρd / (π (1 − ρd F̄int(η)))
//             + Σ_k F_Schlick(θd'; F0_k) D(θh'; α_k) G(ωi', ωo'; α_k) / (4 cos θi' cos θo')
//
// where ωi', ωo' are ωi, ωo refracted into the coat (Snell, about the macro normal), F is the dielectric
// Fresnel reflectance of the coat (η its refractive index) and the 1/η² is the radiance change across the
// interface. The diffuse part's light that the coat's underside reflects back down (F̄int, the internal
// diffuse reflectance: 0.596 at η = 1.5) returns to the base and is summed as a geometric series, as for a
// diffuse base under a smooth dielectric (Mitsuba's "plastic"), so a white base under the coat keeps all the
// energy that enters; the flake lobes, whose light leaves mostly within the escape cone, are single
// scattering (Weidlich and Wilkie's approximation). Why this model for car paint: its dozen numbers reproduce the three
// things a viewer sees — the coat's sharp highlight, the flakes' broader coloured glow that changes with
// angle (the "flop"; pearl paints by lobes of different colours) and the pigment's colour — where a measured
// table takes 35 MB, and it can be fitted to such a table (sdb/car_paint_brdf.h: fitCarPaint). The SDB reads and fits it;
// the baker evaluates and samples it (raytracer/car_paint_lobe.h), so it lives in base.
#pragma once

#include <array>
#include <string>

#include "base/color.h"
#include "base/math.h"

namespace fly {

struct CarPaintLobe {
  Rgb f0{0.0f};        // the flakes' reflectance at normal incidence (Schlick), [0, 1] each; 0 = no lobe
  float alpha = 0.3f;  // GGX width, [0.01, 1]
  bool operator==(const CarPaintLobe&) const = default;
};

struct CarPaintBrdf {
  static constexpr int kMaxLobes = 3;
  Rgb baseAlbedo{0.0f};  // the pigment's Lambertian albedo ρd, [0, 1] each
  std::array<CarPaintLobe, kMaxLobes> lobes{};
  float coatIor = 1.5f;     // the clear coat's refractive index η, [1, 3]; 1 = no coat
  float coatAlpha = 0.02f;  // the coat's GGX width αc, [0.001, 1]

  // f in 1/sr for unit directions in the local frame (z = normal); 0 when either lies below the surface.
  Rgb evalPerSr(const vec3& wiLocal, const vec3& woLocal) const;
  // "" when every parameter lies in its range, else which one does not.
  std::string validate() const;
  bool operator==(const CarPaintBrdf&) const = default;
};

// Unpolarised Fresnel reflectance of a dielectric interface of relative index η for light arriving at cos θ
// from the outside (1 for total internal reflection, which cannot happen from the outside when η ≥ 1).
float dielectricFresnel(float cosTheta, float eta);

// F̄int: the fraction of diffuse (cosine-distributed) light inside a layer of index η ≥ 1 that its surface
// reflects back in, 1 − (1 − F̄ext)/η² with F̄ext = ∫ F(cos θ, η) 2 cos θ sin θ dθ by quadrature (0 for η = 1).
float internalDiffuseReflectance(float eta);

// ω (unit, local frame, ω.z > 0) refracted into a layer of index η ≥ 1 under a smooth interface, as the
// direction inside that points away from the surface (Snell's law about the macro normal).
vec3 refractIntoLayer(const vec3& w, float eta);

}  // namespace fly
