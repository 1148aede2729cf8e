#include "sdb/gltf_anisotropy.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

namespace fly::sdb {

namespace {

// anisotropicLobe in double precision, so that equal widths give back the roughness they came from.
AnisotropicLobe lobeOfWidths(double alphaAlong, double alphaAcross) {
  AnisotropicLobe lobe;
  const double along = std::clamp(alphaAlong, 0.0, 1.0);
  const double across = std::clamp(alphaAcross, 0.0, along);
  if (along <= 0.0) return lobe;  // a mirror both ways
  double ratio = across / along;  // a² of ggxAnisotropicAlphas, (0, 1]
  if (ratio < 1.0 / double(kMaxAnisotropicWidthRatio)) {
    ratio = 1.0 / double(kMaxAnisotropicWidthRatio);
    lobe.clamped = true;
  }
  // α_f = α_along · a: then α_f / a = α_along and α_f · a = α_along · ratio (= α_across unless clamped).
  lobe.glossiness = float(std::sqrt(along * std::sqrt(ratio)));
  lobe.anisotropyU = float(std::min(1.0, (1.0 - ratio) / 0.9));
  return lobe;
}

AnisotropicLobe lobeOfGltf(double roughness, double strength) {
  const double alpha = roughness * roughness;
  return lobeOfWidths(alpha + (1.0 - alpha) * strength * strength, alpha);
}

// Channel c of texel (x, y) of a decoded image, in [0, 1].
double value(const Texture& t, int x, int y, int c) {
  const size_t at = (size_t(y) * size_t(t.width) + size_t(x)) * size_t(t.channels) + size_t(c);
  if (t.bitsPerChannel == 16) {
    uint16_t v;
    std::memcpy(&v, &t.pixels[2 * at], 2);
    return double(v) / 65535.0;
  }
  return double(t.pixels[at]) / 255.0;
}

int64_t wrapIndex(int64_t i, int64_t n, WrapMode mode) {
  switch (mode) {
    case WrapMode::kClampToEdge:
      return std::clamp<int64_t>(i, 0, n - 1);
    case WrapMode::kMirroredRepeat: {
      const int64_t p = ((i % (2 * n)) + 2 * n) % (2 * n);
      return p < n ? p : 2 * n - 1 - p;
    }
    case WrapMode::kRepeat:
      break;
  }
  return ((i % n) + n) % n;
}

// Channel c of `t` bilinearly at texture coordinates (u, v) (the image's top left at (0, 0)), texel centres
// at half-integers, as the engines sample it.
double bilinear(const Texture& t, int c, double u, double v, WrapMode wrapS, WrapMode wrapT) {
  const double x = u * t.width - 0.5, y = v * t.height - 0.5;
  const double x0 = std::floor(x), y0 = std::floor(y);
  const double fx = x - x0, fy = y - y0;
  const int xa = int(wrapIndex(int64_t(x0), t.width, wrapS)),
            xb = int(wrapIndex(int64_t(x0) + 1, t.width, wrapS));
  const int ya = int(wrapIndex(int64_t(y0), t.height, wrapT)),
            yb = int(wrapIndex(int64_t(y0) + 1, t.height, wrapT));
  return (1.0 - fy) * ((1.0 - fx) * value(t, xa, ya, c) + fx * value(t, xb, ya, c)) +
         fy * ((1.0 - fx) * value(t, xa, yb, c) + fx * value(t, xb, yb, c));
}

uint8_t quantise(double v) {
  return uint8_t(std::lround(std::clamp(v, 0.0, 1.0) * 255.0));
}

Texture gridTexture(int width, int height, int channels) {
  Texture t;
  t.width = width;
  t.height = height;
  t.channels = channels;
  t.bitsPerChannel = 8;
  t.pixels.assign(size_t(width) * size_t(height) * size_t(channels), 0);
  return t;
}

// The start φ0 of the half turn [φ0, φ0 + π) in which rotations are stored modulo π: the middle of the widest
// interval of directions (modulo π, in 0.5° bins) that no anisotropic texel points along, else of the bin
// with the least anisotropy (the sum of U).
double halfTurnSeam(const std::vector<float>& u, const std::vector<double>& angle) {
  constexpr int kBins = 360;
  std::array<double, kBins> weight{};
  for (size_t i = 0; i < u.size(); ++i) {
    double a = std::fmod(angle[i], kPi);
    if (a < 0.0) a += kPi;
    weight[size_t(std::min(kBins - 1, int(a / kPi * kBins)))] += u[i];
  }
  int bestStart = int(std::min_element(weight.begin(), weight.end()) - weight.begin()), bestLength = 1;
  if (weight[size_t(bestStart)] == 0.0) {
    // The longest circular run of empty bins; it starts after an occupied one (some bin is occupied).
    for (int start = 0; start < kBins; ++start) {
      if (weight[size_t(start)] != 0.0 || weight[size_t((start + kBins - 1) % kBins)] == 0.0) continue;
      int length = 0;
      while (weight[size_t((start + length) % kBins)] == 0.0) ++length;
      if (length > bestLength) {
        bestStart = start;
        bestLength = length;
      }
    }
  }
  return std::fmod((bestStart + 0.5 * bestLength) * kPi / kBins, kPi);
}

// The rotation texture's red (× 2π = the rotation) for the angles of one encoding: `period` π stores each
// angle in [seam, seam + π); `period` 2π stores the direction's own angle plus `seam` (0 or π, either being
// the same lobe) in [0, 2π), which follows a direction field that turns a full circle (a disc's) with one
// jump instead of two.
std::vector<uint8_t> encodeRotations(const std::vector<double>& angle, double period, double seam) {
  std::vector<uint8_t> red(angle.size());
  for (size_t i = 0; i < angle.size(); ++i) {
    double a = std::fmod(angle[i] - seam, period);
    if (a < 0.0) a += period;
    const double stored = period == kPi ? seam + a : a;
    red[i] = quantise(stored / (2.0 * kPi));
  }
  return red;
}

// Where bilinear filtering of `red` mixes unrelated rotations: the anisotropy (the smaller U) of neighbouring
// texels, along rows and columns, whose stored rotations are more than a quarter turn apart.
double jumps(const std::vector<uint8_t>& red, const std::vector<float>& u, int width, int height) {
  double sum = 0.0;
  const auto pair = [&](size_t a, size_t b) {
    if (std::abs(int(red[a]) - int(red[b])) > 64) sum += std::min(u[a], u[b]);
  };
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const size_t i = size_t(y) * size_t(width) + size_t(x);
      if (x + 1 < width) pair(i, i + 1);
      if (y + 1 < height) pair(i, i + size_t(width));
    }
  }
  return sum;
}

}  // namespace

vec2 gltfAnisotropicAlphas(float roughness, float strength) {
  const float alpha = roughness * roughness;
  return {alpha + (1.0f - alpha) * strength * strength, alpha};
}

AnisotropicLobe anisotropicLobe(float alphaAlong, float alphaAcross) {
  return lobeOfWidths(double(alphaAlong), double(alphaAcross));
}

GltfAnisotropyConversion convertGltfAnisotropy(const GltfAnisotropyInput& in) {
  GltfAnisotropyConversion out;
  const Texture* const aniso = in.anisotropyTexture;
  const Texture* const rough = in.roughnessTexture;
  const Texture* const grid = aniso ? aniso : rough;
  const int width = grid ? grid->width : 1;
  const int height = grid ? grid->height : 1;
  const bool resample = aniso && rough && (rough->width != aniso->width || rough->height != aniso->height);
  const size_t n = size_t(width) * size_t(height);
  out.texels = n;
  std::vector<float> glossiness(n), u(n);
  std::vector<double> angle(n);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const size_t i = size_t(y) * size_t(width) + size_t(x);
      double roughness = in.roughness;
      if (rough) {
        roughness *= resample ? bilinear(*rough, 1, (x + 0.5) / width, (y + 0.5) / height, in.roughnessWrapS,
                                         in.roughnessWrapT)
                              : value(*rough, x, y, 1);
      }
      double strength = in.strength;
      angle[i] = in.rotationRad;
      if (aniso) {
        // The direction (red, green → [−1, 1]) turned by the rotation; only its angle matters (the
        // extension normalises it). atan2(0, 0) = 0 keeps the rotation for a texel without a direction.
        angle[i] += std::atan2(2.0 * value(*aniso, x, y, 1) - 1.0, 2.0 * value(*aniso, x, y, 0) - 1.0);
        strength *= value(*aniso, x, y, 2);
      }
      const AnisotropicLobe lobe = lobeOfGltf(roughness, strength);
      glossiness[i] = lobe.glossiness;
      u[i] = lobe.anisotropyU;
      if (lobe.clamped) ++out.clampedTexels;
    }
  }
  const float maxU = *std::max_element(u.begin(), u.end());
  if (maxU <= 0.0f) return out;
  out.anisotropic = true;

  const float maxGlossiness = *std::max_element(glossiness.begin(), glossiness.end());
  out.glossiness = maxGlossiness;
  if (std::any_of(glossiness.begin(), glossiness.end(), [&](float g) { return g != glossiness[0]; })) {
    out.glossinessTexture = gridTexture(width, height, 1);
    for (size_t i = 0; i < n; ++i) out.glossinessTexture->pixels[i] = quantise(glossiness[i] / maxGlossiness);
  }
  out.anisotropyU = maxU;
  if (std::any_of(u.begin(), u.end(), [&](float v) { return v != u[0]; })) {
    out.anisotropyTexture = gridTexture(width, height, 3);
    for (size_t i = 0; i < n; ++i) out.anisotropyTexture->pixels[3 * i] = quantise(u[i]);
  }
  // The rotation matters only where the lobe is anisotropic.
  size_t first = 0;
  while (u[first] <= 0.0f) ++first;
  out.rotationRad = float(angle[first]);
  bool oneRotation = true;
  for (size_t i = first; i < n && oneRotation; ++i) oneRotation = u[i] <= 0.0f || angle[i] == angle[first];
  if (!oneRotation) {
    // Of three encodings, the one with the fewest jumps between neighbours: modulo a half turn with its wrap
    // where no texel points, or the direction's own angle (modulo a full turn), taken as it is or turned by
    // a half turn.
    out.rotationRad = 0.0f;
    out.rotationTexture = gridTexture(width, height, 1);
    std::vector<uint8_t>& best = out.rotationTexture->pixels;
    best = encodeRotations(angle, kPi, halfTurnSeam(u, angle));
    double bestJumps = jumps(best, u, width, height);
    for (const double seam : {0.0, kPi}) {
      std::vector<uint8_t> red = encodeRotations(angle, 2.0 * kPi, seam);
      const double j = jumps(red, u, width, height);
      if (j < bestJumps) {
        best = std::move(red);
        bestJumps = j;
      }
    }
  }
  return out;
}

}  // namespace fly::sdb
