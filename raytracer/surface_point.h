// A material at a point of a surface: texture lookups (bilinear, glTF wrap modes, KHR_texture_transform, sRGB
// decoding), COLOR_0, alpha coverage, the TraceMaterial whose colours are those of the point (the realistic
// material's energy rule applied to them there), the shading normal (interpolated vertex normals and
// normal maps) and the shading frame (the tangents of anisotropic materials). What the integrator evaluates
// at a ray hit on a material that varies over its surface, and what the Embree filter asks of an alpha
// cut-out.
#pragma once

#include <cstdint>

#include "base/color.h"
#include "base/math.h"
#include "raytracer/warp.h"
#include "rdb/trace_rdb.h"

namespace fly::raytracer {

// The texel index for integer texel coordinate i of an image `size` texels wide under wrap mode w (OpenGL's
// rules: repeat i mod size, clamp to [0, size − 1], mirror with period 2 · size).
uint32_t wrapTexel(int64_t i, uint32_t size, rdb::TraceWrap w);

// The slot's texture at texture coordinates uv (of the slot's UV set, before its transform), filtered
// bilinearly between the four nearest texel centres (texel (i, j) is centred at ((i + ½)/width, (j +
// ½)/height), row j = 0 at v = 0, the image's top row), or for a slot.nearest the texel that contains the
// point (texel (i, j) covers [i/width, (i+1)/width) × [j/height, (j+1)/height), as OpenGL's NEAREST). Returns linear RGBA: a grey texture's value in r, g
// and b, alpha 1 where the texture has none. srgb: the colour channels (not alpha) are sRGB-encoded (IEC
// 61966-2-1) and are decoded per texel before filtering. Non-finite coordinates read the texel at (0, 0).
vec4 sampleTexture(const rdb::TraceRdb& rdb, const rdb::TraceTextureSlot& slot, const vec2& uv, bool srgb);

// Barycentrics (u, v) of a point on triangle t: (1 − u − v)·p0 + u·p1 + v·p2, as Embree reports them.
struct TrianglePoint {
  uint32_t triangle = 0;
  vec2 barycentric{0.0f};
};

// The texture coordinates of set `set` (0 or 1) at a point, (0, 0) when the TraceRdb has none.
vec2 interpolateUv(const rdb::TraceRdb& rdb, uint32_t set, const TrianglePoint& at);

// Coverage at a point (TraceMaterial): opacity × the diffuse texture's alpha × COLOR_0's alpha, in [0, 1].
float coverageAt(const rdb::TraceRdb& rdb, const rdb::TraceMaterial& m, const TrianglePoint& at);

// A material at a point: its textured colours, the energy rule applied at normal incidence as lowerMaterial
// does for the constants (bsdf.h: normalIncidenceDiffuse), no texture slots left; and its coverage.
struct PointMaterial {
  rdb::TraceMaterial material;
  float coverage = 1.0f;
};
PointMaterial materialAt(const rdb::TraceRdb& rdb, const rdb::TraceMaterial& m, const TrianglePoint& at);

// The emitted luminance at a point, cd/m²: emissionCdM2 × the emission texture's colour, × coverage for
// partial coverage (a BLEND surface composites all of its colour, emission included, by its alpha).
Rgb emissionAt(const rdb::TraceRdb& rdb, const rdb::TraceMaterial& m, const TrianglePoint& at);

// The shading normal of the front face at a point: the interpolated vertex normals, bent by the material's
// normal map (tangent space: the interpolated tangent T made perpendicular to the normal N, B = w · N × T,
// the map's x and y scaled by normalScale). It is replaced by geometricNormal (unit, the front face's) where
// it is degenerate or points to the back of the surface.
vec3 shadingNormalAt(const rdb::TraceRdb& rdb, const rdb::TraceMaterial& m, const TrianglePoint& at,
                     const vec3& geometricNormal);

// The local frame in which a Bsdf of material m shades the point, around the unit shading normal n of the
// side being lit (front: the front face's side). For anisotropic materials (TraceMaterial::isAnisotropic),
// whose lobe's axes follow the surface: +x the interpolated vertex tangent made perpendicular to n, +y the
// bitangent w · N × T of the front face (N = n on the front, −n on the back, so that both faces turn the
// anisotropy the same way on the surface); any basis around n where that tangent is degenerate. For all
// others, whose lobes are symmetric about the normal: any basis around n (onb).
Onb shadingFrameAt(const rdb::TraceRdb& rdb, const rdb::TraceMaterial& m, const TrianglePoint& at,
                   const vec3& n, bool front);

}  // namespace fly::raytracer
