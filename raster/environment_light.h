// Image-based light: an environment of radiance over all directions (the sky, or an image the user gives),
// turned into what a per-pixel material needs to be lit by it in real time — the split-sum approximation of
// Karis ("Real Shading in Unreal Engine 4", SIGGRAPH 2013 course), with fly's GGX:
//   - the environment as a cube map with a box-filtered mip chain (the source);
//   - a radiance cube whose mip level k is the environment prefiltered by the GGX lobe of α_k = (k/(K − 1))²
//     about the reflection direction (L_pre(r, α)), for glossy reflection;
//   - an irradiance cube, E(n) = ∫ L max(0, n·ω) dω in lux, for diffuse light (by quadrature, not spherical
//     harmonics, so a sharp horizon is not rung);
//   - the split sum's table (A, B)(cos θo, √α), so that the reflected radiance of a GGX lobe with Schlick's
//     F0 is L_pre(r, α) · (F0 A + B).
// Units: radiance in cd/m², irradiance in lux; world directions (+Y up). Needs a current context.
#pragma once

#include <cstdint>
#include <functional>
#include <initializer_list>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "base/color.h"
#include "base/math.h"

namespace fly::raster {

struct EnvironmentSettings {
  uint32_t cubePx = 128;           // the source and radiance cubes' face size at level 0, [8, 2048]
  uint32_t radianceLevels = 6;     // prefiltered levels, α_k = (k/(K − 1))², [2, log2(cubePx) + 1]
  uint32_t prefilterSamples = 1024;  // GGX directions per texel of the prefiltered levels, [16, 65536]
  uint32_t irradiancePx = 16;      // the irradiance cube's face size, [1, 256]
  uint32_t irradianceQuadPx = 32;  // the source level summed over for the irradiance, a power of 2 ≤ cubePx
  uint32_t tablePx = 64;           // the split-sum table, N × N, [8, 1024]
  uint32_t tableSamples = 1024;    // per table texel, [16, 65536]

  bool operator==(const EnvironmentSettings&) const = default;
};

class EnvironmentLight {
 public:
  // Compiles and links a program of (GL shader type, source) stages (raster/gl_program.h, or the renderer's).
  using Compile = std::function<unsigned(const std::string& name, const std::string& defines,
                                         std::initializer_list<std::pair<unsigned, const char*>> stages)>;
  // std::invalid_argument when a setting is out of range.
  EnvironmentLight(Compile compile, const EnvironmentSettings& settings = {});
  ~EnvironmentLight();
  EnvironmentLight(const EnvironmentLight&) = delete;
  EnvironmentLight& operator=(const EnvironmentLight&) = delete;

  // Builds every map from an equirectangular GL texture (sampler2D, RGB cd/m²; u = φ/2π with φ = atan2(z, x),
  // v = θ/π from the zenith, as rdb::RasterSky), e.g. the renderer's sky image.
  void build(unsigned equirectTexture);
  // The same from pixels: width × height, rows from the zenith; std::invalid_argument for an empty image or
  // a value that is negative or not finite (naming the pixel).
  void build(const std::vector<Rgb>& radianceCdM2, uint32_t width, uint32_t height);
  // The same from a cube the caller renders: sourceCube() is the source's texture (GL_TEXTURE_CUBE_MAP,
  // RGBA32F, cubePx² a face; write level 0, e.g. by image stores, then make them visible), buildFromSource()
  // makes the rest from its level 0.
  unsigned sourceCube();
  void buildFromSource();

  const EnvironmentSettings& settings() const { return settings_; }
  unsigned radianceCube() const;    // GL_TEXTURE_CUBE_MAP, RGBA32F, radianceLevels mip levels
  unsigned irradianceCube() const;  // GL_TEXTURE_CUBE_MAP, RGBA32F, lux
  unsigned splitSumTable() const;   // GL_TEXTURE_2D, RG32F, (A, B)
  // The GGX α of radiance level k.
  float levelAlpha(uint32_t k) const;

  // Read-backs for tests: a face (0 … 5 = +X, −X, +Y, −Y, +Z, −Z) of a level, RGB, n × n rows from t = −1;
  // the table, (A, B) pairs, rows of √α from the smallest.
  std::vector<Rgb> readRadiance(uint32_t level, uint32_t face) const;
  std::vector<Rgb> readIrradiance(uint32_t face) const;
  std::vector<vec2> readSplitSum() const;

 private:
  struct Gpu;
  std::unique_ptr<Gpu> gpu_;
  Compile compile_;
  EnvironmentSettings settings_;
};

// The split sum's table alone, as EnvironmentLight makes it: (A, B)(cos θo, √α), tablePx² RG32F (linear
// filtering, clamped to the edge), tableSamples GGX samples a texel — for passes that need a GGX lobe's
// albedo without an environment (frosted glass's transmittance, raster/renderer.h). The caller owns the
// texture. Ranges as EnvironmentSettings'.
unsigned makeSplitSumTable(const EnvironmentLight::Compile& compile, uint32_t tablePx, uint32_t tableSamples);

}  // namespace fly::raster
