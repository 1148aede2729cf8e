#include "raytracer/surface_point.h"

#include <array>
#include <cmath>

#include "raytracer/bsdf.h"

namespace fly::raytracer {
namespace {

// sRGB-encoded byte → linear value.
const std::array<float, 256>& srgbTable() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) t[size_t(i)] = srgbToLinear(float(i) / 255.0f);
    return t;
  }();
  return table;
}

// Texel (x, y) as linear RGBA (TraceTexture's channel layouts).
vec4 texel(const rdb::TraceTexture& t, uint32_t x, uint32_t y, bool srgb) {
  const uint8_t* p = t.texels.data() + (size_t(y) * t.width + x) * t.channels;
  const std::array<float, 256>& table = srgbTable();
  auto colour = [&](uint8_t v) { return srgb ? table[v] : float(v) * (1.0f / 255.0f); };
  switch (t.channels) {
    case 1:
      return vec4(vec3(colour(p[0])), 1.0f);
    case 2:
      return vec4(vec3(colour(p[0])), float(p[1]) * (1.0f / 255.0f));
    case 3:
      return vec4(colour(p[0]), colour(p[1]), colour(p[2]), 1.0f);
    default:
      return vec4(colour(p[0]), colour(p[1]), colour(p[2]), float(p[3]) * (1.0f / 255.0f));
  }
}

// The three vertex indices of triangle t.
const uint32_t* corners(const rdb::TraceRdb& rdb, uint32_t t) {
  return &rdb.indices[3 * size_t{t}];
}

template <class T>
T interpolate(const std::vector<T>& values, const uint32_t* v, const vec2& b) {
  return (1.0f - b.x - b.y) * values[v[0]] + b.x * values[v[1]] + b.y * values[v[2]];
}

vec2 slotUv(const rdb::TraceRdb& rdb, const rdb::TraceTextureSlot& slot, const TrianglePoint& at) {
  return interpolateUv(rdb, slot.texCoord, at);
}

}  // namespace

uint32_t wrapTexel(int64_t i, uint32_t size, rdb::TraceWrap w) {
  const auto n = int64_t{size};
  switch (w) {
    case rdb::TraceWrap::kClampToEdge:
      return uint32_t(std::clamp<int64_t>(i, 0, n - 1));
    case rdb::TraceWrap::kMirroredRepeat: {
      int64_t m = i % (2 * n);
      if (m < 0) m += 2 * n;
      return uint32_t(m < n ? m : 2 * n - 1 - m);
    }
    case rdb::TraceWrap::kRepeat:
      break;
  }
  int64_t m = i % n;
  if (m < 0) m += n;
  return uint32_t(m);
}

vec4 sampleTexture(const rdb::TraceRdb& rdb, const rdb::TraceTextureSlot& slot, const vec2& uv, bool srgb) {
  const rdb::TraceTexture& t = rdb.textures[slot.texture];
  vec2 st = slot.uvFromU * uv.x + slot.uvFromV * uv.y + slot.uvOffset;
  if (!isFinite(st)) st = vec2(0.0f);
  // Texel space, centres at integers; clamped far outside any image so that the integer part stays exact
  // (2^24 texels: every wrap mode has long since repeated or clamped).
  if (slot.nearest) {
    const float x = std::clamp(std::floor(st.x * float(t.width)), -0x1p24f, 0x1p24f);
    const float y = std::clamp(std::floor(st.y * float(t.height)), -0x1p24f, 0x1p24f);
    return texel(t, wrapTexel(int64_t(x), t.width, slot.wrapS), wrapTexel(int64_t(y), t.height, slot.wrapT), srgb);
  }
  const float x = std::clamp(st.x * float(t.width) - 0.5f, -0x1p24f, 0x1p24f);
  const float y = std::clamp(st.y * float(t.height) - 0.5f, -0x1p24f, 0x1p24f);
  const float x0f = std::floor(x);
  const float y0f = std::floor(y);
  const float fx = x - x0f;
  const float fy = y - y0f;
  const auto x0 = int64_t(x0f);
  const auto y0 = int64_t(y0f);
  const uint32_t xa = wrapTexel(x0, t.width, slot.wrapS), xb = wrapTexel(x0 + 1, t.width, slot.wrapS);
  const uint32_t ya = wrapTexel(y0, t.height, slot.wrapT), yb = wrapTexel(y0 + 1, t.height, slot.wrapT);
  return (1.0f - fy) * ((1.0f - fx) * texel(t, xa, ya, srgb) + fx * texel(t, xb, ya, srgb)) +
         fy * ((1.0f - fx) * texel(t, xa, yb, srgb) + fx * texel(t, xb, yb, srgb));
}

vec2 interpolateUv(const rdb::TraceRdb& rdb, uint32_t set, const TrianglePoint& at) {
  const std::vector<vec2>& uv = set == 1 ? rdb.uv1 : rdb.uv0;
  if (uv.empty()) return vec2(0.0f);
  return interpolate(uv, corners(rdb, at.triangle), at.barycentric);
}

float coverageAt(const rdb::TraceRdb& rdb, const rdb::TraceMaterial& m, const TrianglePoint& at) {
  float c = m.opacity;
  if (m.diffuseTexture) c *= sampleTexture(rdb, m.diffuseTexture, slotUv(rdb, m.diffuseTexture, at), true).a;
  if (!rdb.colors.empty()) c *= interpolate(rdb.colors, corners(rdb, at.triangle), at.barycentric).a;
  return std::clamp(c, 0.0f, 1.0f);
}

PointMaterial materialAt(const rdb::TraceRdb& rdb, const rdb::TraceMaterial& m, const TrianglePoint& at) {
  PointMaterial p;
  rdb::TraceMaterial& out = p.material;
  out = m;
  float coverage = m.opacity;
  Rgb diffuse = m.diffuseColor;
  if (m.diffuseTexture) {
    const vec4 base = sampleTexture(rdb, m.diffuseTexture, slotUv(rdb, m.diffuseTexture, at), true);
    diffuse *= Rgb(base);
    coverage *= base.a;
  }
  if (!rdb.colors.empty()) {
    const vec4 colour = interpolate(rdb.colors, corners(rdb, at.triangle), at.barycentric);
    diffuse *= Rgb(colour);
    coverage *= colour.a;
  }
  if (m.reflectionTexture) {
    out.reflection *=
        Rgb(sampleTexture(rdb, m.reflectionTexture, slotUv(rdb, m.reflectionTexture, at),
                            m.reflectionTextureSrgb));
  }
  if (m.glossinessTexture) {
    out.reflectionGlossiness *=
        sampleTexture(rdb, m.glossinessTexture, slotUv(rdb, m.glossinessTexture, at), false).r;
  }
  if (m.transmissionTexture) {
    out.transmission *=
        Rgb(sampleTexture(rdb, m.transmissionTexture, slotUv(rdb, m.transmissionTexture, at), false));
  }
  if (m.anisotropyTexture) {
    const vec4 uv = sampleTexture(rdb, m.anisotropyTexture, slotUv(rdb, m.anisotropyTexture, at), false);
    out.anisotropyU = uv.r;
    out.anisotropyV = uv.g;
  }
  if (m.anisotropyRotationTexture) {
    const vec4 turns =
        sampleTexture(rdb, m.anisotropyRotationTexture, slotUv(rdb, m.anisotropyRotationTexture, at), false);
    out.anisotropyRotationRad = 2.0f * kPiF * turns.r;
  }
  if (m.metalnessTexture) {
    out.metalness = std::clamp(
        m.metalness * sampleTexture(rdb, m.metalnessTexture, slotUv(rdb, m.metalnessTexture, at), false).r, 0.0f,
        1.0f);
  }
  out.emissionCdM2 = emissionAt(rdb, m, at);
  out.diffuseColor = glm::clamp(diffuse, 0.0f, 1.0f);
  out.diffuse = normalIncidenceDiffuse(out);
  out.diffuseTexture = out.reflectionTexture = out.glossinessTexture = out.transmissionTexture =
      out.emissionTexture = out.normalTexture = out.anisotropyTexture = out.anisotropyRotationTexture =
          out.metalnessTexture = rdb::TraceTextureSlot{};
  p.coverage = std::clamp(coverage, 0.0f, 1.0f);
  return p;
}

Rgb emissionAt(const rdb::TraceRdb& rdb, const rdb::TraceMaterial& m, const TrianglePoint& at) {
  Rgb e = m.emissionCdM2;
  if (m.emissionTexture) {
    e *= Rgb(sampleTexture(rdb, m.emissionTexture, slotUv(rdb, m.emissionTexture, at), true));
  }
  return m.alpha == rdb::TraceAlpha::kBlend ? e * coverageAt(rdb, m, at) : e;
}

vec3 shadingNormalAt(const rdb::TraceRdb& rdb, const rdb::TraceMaterial& m, const TrianglePoint& at,
                     const vec3& geometricNormal) {
  const uint32_t* v = corners(rdb, at.triangle);
  vec3 n = interpolate(rdb.normals, v, at.barycentric);
  const float len = glm::length(n);
  if (!(len > 0.0f) || !std::isfinite(len)) return geometricNormal;
  n /= len;
  if (m.normalTexture && !rdb.tangents.empty()) {
    const vec4 t4 = interpolate(rdb.tangents, v, at.barycentric);
    const vec3 t = vec3(t4) - glm::dot(vec3(t4), n) * n;
    const float tl = glm::length(t);
    if (tl > 1e-6f && std::isfinite(tl)) {
      const vec3 tangent = t / tl;
      const float w = rdb.tangents[v[0]].w < 0.0f ? -1.0f : 1.0f;
      const vec3 bitangent = w * glm::cross(n, tangent);
      const vec3 map = vec3(sampleTexture(rdb, m.normalTexture, slotUv(rdb, m.normalTexture, at), false));
      const vec3 local = (2.0f * map - 1.0f) * vec3(m.normalScale, m.normalScale, 1.0f);
      const vec3 bent = local.x * tangent + local.y * bitangent + local.z * n;
      const float bl = glm::length(bent);
      if (bl > 0.0f && std::isfinite(bl)) n = bent / bl;
    }
  }
  return glm::dot(n, geometricNormal) > 0.0f ? n : geometricNormal;
}

Onb shadingFrameAt(const rdb::TraceRdb& rdb, const rdb::TraceMaterial& m, const TrianglePoint& at,
                   const vec3& n, bool front) {
  if (!m.isAnisotropic() || rdb.tangents.empty()) return onb(n);
  const uint32_t* v = corners(rdb, at.triangle);
  const vec3 t4 = vec3(interpolate(rdb.tangents, v, at.barycentric));
  const vec3 t = t4 - glm::dot(t4, n) * n;
  const float tl = glm::length(t);
  if (!(tl > 1e-6f) || !std::isfinite(tl)) return onb(n);
  const vec3 tangent = t / tl;
  // B = w · N × T with N the front face's normal: n on the front, −n on the back.
  const float w = (rdb.tangents[v[0]].w < 0.0f ? -1.0f : 1.0f) * (front ? 1.0f : -1.0f);
  return Onb{tangent, w * glm::cross(n, tangent), n};
}

}  // namespace fly::raytracer
