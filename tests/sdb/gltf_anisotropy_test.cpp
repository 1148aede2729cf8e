// KHR_materials_anisotropy → the realistic material's anisotropy (sdb/gltf_anisotropy.h): the widths the
// extension defines (α along its direction = mix(α, 1, strength²), α across, α = roughness²) against the
// widths fly's lobe has (base/ggx.h, ggxAnisotropicAlphas), its direction, its textures, and bad values.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <string>
#include <tuple>

#include "base/ggx.h"
#include "gltf_import_fixture.h"
#include "sdb/gltf_anisotropy.h"

namespace fly::sdb {
namespace {

using json = nlohmann::json;
using test::GltfBuilder;

// The extension's widths, written out from its specification ("Anisotropy"): x along the direction, y across.
vec2 specWidths(double roughness, double strength) {
  const double alpha = roughness * roughness;
  return vec2(float(alpha * (1.0 - strength * strength) + 1.0 * strength * strength), float(alpha));
}

// fly's GGX widths of glossiness g and anisotropy (u, v): x along U, y along V.
vec2 flyWidths(float glossiness, float u, float v) {
  return ggxAnisotropicAlphas(glossiness * glossiness, u, v);
}

// The width of the lobe seen along the tangent-plane direction at angle φ from the tangent (towards the
// bitangent), for a lobe of widths (along, across) whose long axis lies at angle ρ: the GGX slope
// distribution's width projected on that direction, √(α_along² cos²(φ − ρ) + α_across² sin²(φ − ρ)) (Heitz
// 2014, eq. 80).
double projectedWidth(vec2 widths, double rho, double phi) {
  const double c = std::cos(phi - rho), s = std::sin(phi - rho);
  return std::sqrt(double(widths.x) * widths.x * c * c + double(widths.y) * widths.y * s * s);
}

json anisotropic(double roughness, const json& extension) {
  return {{"pbrMetallicRoughness", {{"metallicFactor", 1}, {"roughnessFactor", roughness}}},
          {"extensions", {{"KHR_materials_anisotropy", extension}}}};
}

TEST_F(GltfImport, AnisotropyOfStrengthZeroLeavesTheLobeIsotropic) {
  GltfBuilder b = withMaterial(anisotropic(0.4, {{"anisotropyStrength", 0.0}, {"anisotropyRotation", 1.0}}));
  b.useExtension("KHR_materials_anisotropy", true);
  const GltfImportResult r = import(b);
  const Material& m = onlyMaterialOfMesh();
  EXPECT_FALSE(m.isAnisotropic());
  EXPECT_EQ(m.reflectionGlossiness, 0.4f);
  EXPECT_EQ(m.anisotropyU, 0.0f);
  EXPECT_EQ(m.anisotropyV, 0.0f);
  EXPECT_TRUE(scene_.textures().empty());
  EXPECT_TRUE(r.warnings.empty()) << r.warnings[0];
}

// Strength s and roughness r give the extension's widths exactly while they are at most 10:1 apart.
TEST_F(GltfImport, AnisotropyGivesTheWidthsOfTheExtension) {
  for (const auto& [roughness, strength] : {std::pair{0.5, 1.0}, {0.6, 0.5}, {0.35, 0.9}, {0.8, 0.2}}) {
    SCOPED_TRACE(testing::Message() << "roughness " << roughness << ", strength " << strength);
    Scene scene;
    GltfBuilder b = withMaterial(anisotropic(roughness, {{"anisotropyStrength", strength}}));
    b.writeGltf(dir_ / "a.gltf");
    const GltfImportResult r = importGltf(scene, dir_ / "a.gltf");
    const Material& m = scene.materials().begin()->second;
    EXPECT_TRUE(m.isAnisotropic());
    EXPECT_EQ(m.anisotropyV, 0.0f);
    EXPECT_EQ(m.anisotropyRotationRad, 0.0f);
    const vec2 expected = specWidths(roughness, strength);
    const vec2 widths = flyWidths(m.reflectionGlossiness, m.anisotropyU, m.anisotropyV);
    EXPECT_NEAR(widths.x, expected.x, 2e-6f * expected.x);
    EXPECT_NEAR(widths.y, expected.y, 2e-6f * expected.y);
    EXPECT_TRUE(scene.textures().empty());
    EXPECT_TRUE(r.warnings.empty()) << r.warnings[0];
  }
  // Roughness 0.5, strength 1: α = 0.25 and α_d = 1; glossiness = (α_d α)^¼ = √½, U = (1 − α/α_d)/0.9 = 5/6.
  GltfBuilder b = withMaterial(anisotropic(0.5, {{"anisotropyStrength", 1.0}}));
  import(b);
  EXPECT_NEAR(onlyMaterialOfMesh().reflectionGlossiness, std::sqrt(0.5f), 1e-7f);
  EXPECT_NEAR(onlyMaterialOfMesh().anisotropyU, 5.0f / 6.0f, 1e-7f);
}

// Roughness 0.1 and strength 1: α_d = 1, α = 0.01, a ratio of 100 where fly's lobe reaches 10; its length
// along the direction is kept and its width across is α_d / 10. So for glTF's mirror (roughness 0) at
// strength ⅙.
TEST_F(GltfImport, AnisotropyBeyondTenToOneKeepsTheLengthAlongTheDirection) {
  const std::tuple<double, double, std::string> cases[] = {
      {0.1, 1.0, "GGX α 1 along, 0.01 across"}, {0.0, 1.0 / 6.0, "GGX α 0.0277778 along, 0 across"}};
  for (const auto& [roughness, strength, asked] : cases) {
    SCOPED_TRACE(testing::Message() << "roughness " << roughness << ", strength " << strength);
    Scene scene;
    GltfBuilder b = withMaterial(anisotropic(roughness, {{"anisotropyStrength", strength}}));
    b.writeGltf(dir_ / "a.gltf");
    const GltfImportResult r = importGltf(scene, dir_ / "a.gltf");
    const Material& m = scene.materials().begin()->second;
    const double along = specWidths(roughness, strength).x;
    const vec2 widths = flyWidths(m.reflectionGlossiness, m.anisotropyU, m.anisotropyV);
    EXPECT_NEAR(widths.x, along, 1e-5 * along);
    EXPECT_NEAR(widths.y, along / 10.0, 1e-5 * along);
    EXPECT_TRUE(contains(
        r.warnings, "material 0: its anisotropy stretches the lobe more than fly's limit of 10:1 (" + asked +
                        "); there the lobe keeps glTF's width along the anisotropy direction"))
        << (r.warnings.empty() ? "no warning" : r.warnings[0]);
  }
}

// anisotropyRotation turns the direction counter-clockwise, from the tangent towards the bitangent, as
// fly's anisotropyRotationRad does: a quarter turn puts the long axis on the bitangent, swapping the widths
// seen along the tangent and the bitangent.
TEST_F(GltfImport, AnisotropyRotationOfAQuarterTurnSwapsTheAxes) {
  const double roughness = 0.5, strength = 0.9;
  const vec2 spec = specWidths(roughness, strength);
  double alongTangent[2], alongBitangent[2];
  for (int k = 0; k < 2; ++k) {
    const double rotation = k * kPi / 2.0;
    Scene scene;
    GltfBuilder b = withMaterial(
        anisotropic(roughness, {{"anisotropyStrength", strength}, {"anisotropyRotation", rotation}}));
    b.writeGltf(dir_ / "a.gltf");
    importGltf(scene, dir_ / "a.gltf");
    const Material& m = scene.materials().begin()->second;
    EXPECT_EQ(m.anisotropyRotationRad, float(rotation));
    const vec2 fly = flyWidths(m.reflectionGlossiness, m.anisotropyU, m.anisotropyV);
    // The widths at every azimuth of the tangent plane, fly's lobe against the extension's.
    for (int i = 0; i < 12; ++i) {
      const double phi = i * kPi / 12.0;
      EXPECT_NEAR(projectedWidth(fly, m.anisotropyRotationRad, phi), projectedWidth(spec, rotation, phi),
                  1e-5)
          << "azimuth " << phi;
    }
    alongTangent[k] = projectedWidth(fly, m.anisotropyRotationRad, 0.0);
    alongBitangent[k] = projectedWidth(fly, m.anisotropyRotationRad, kPi / 2.0);
  }
  EXPECT_NEAR(alongTangent[0], spec.x, 1e-6);    // 0.8275 = 0.25 + 0.75 · 0.81
  EXPECT_NEAR(alongBitangent[0], spec.y, 1e-6);  // 0.25
  EXPECT_NEAR(alongTangent[1], alongBitangent[0], 1e-6);
  EXPECT_NEAR(alongBitangent[1], alongTangent[0], 1e-6);
}

// anisotropyTexture: per texel the direction (red, green → [−1, 1]) turned by anisotropyRotation, and the
// strength times blue. Four texels: along +x, along +y, along −x (the same lobe as +x), and a diagonal of
// strength 0; read back from the converted textures (8 bits: rotation within half a step of 2π/255).
TEST_F(GltfImport, AnisotropyTextureDirectionsBecomeRotationsAndWidthsPerTexel) {
  const std::vector<uint16_t> rgb = {255, 128, 255, 128, 255, 255, 0, 128, 128, 218, 218, 0};
  const double roughness = 0.3, strength = 0.8, rotation = 0.1;
  GltfBuilder b = withMaterial(json::object());
  const int tex = addImageTexture(b, test::png(4, 1, rgb));
  b.append("samplers", {{"wrapS", 33071}, {"wrapT", 33648}, {"magFilter", 9728}});
  b.doc["textures"][tex]["sampler"] = 0;
  b.doc["materials"][0] = anisotropic(roughness, {{"anisotropyStrength", strength},
                                                  {"anisotropyRotation", rotation},
                                                  {"anisotropyTexture", {{"index", tex}, {"texCoord", 1}}}});
  const GltfImportResult r = import(b);
  const Material& m = onlyMaterialOfMesh();
  ASSERT_TRUE(m.anisotropyTexture && m.anisotropyRotationTexture && m.reflectionGlossinessTexture);
  EXPECT_EQ(scene_.textures().size(), 3u);  // the converted ones; the file's image is not kept
  for (const TextureRef* ref :
       {&m.anisotropyTexture, &m.anisotropyRotationTexture, &m.reflectionGlossinessTexture}) {
    EXPECT_EQ(ref->texCoord, 1);
    EXPECT_EQ(ref->wrapS, WrapMode::kClampToEdge);
    EXPECT_EQ(ref->wrapT, WrapMode::kMirroredRepeat);
    EXPECT_EQ(ref->magFilter, MagFilter::kNearest);
    const Texture& t = scene_.texture(ref->texture);
    EXPECT_EQ(t.width, 4);
    EXPECT_EQ(t.height, 1);
    EXPECT_EQ(t.bitsPerChannel, 8);
  }
  const Texture& uv = scene_.texture(m.anisotropyTexture.texture);
  const Texture& turns = scene_.texture(m.anisotropyRotationTexture.texture);
  const Texture& gloss = scene_.texture(m.reflectionGlossinessTexture.texture);
  ASSERT_EQ(uv.channels, 3);
  ASSERT_EQ(turns.channels, 1);
  ASSERT_EQ(gloss.channels, 1);
  for (int i = 0; i < 4; ++i) {
    SCOPED_TRACE(testing::Message() << "texel " << i);
    const double dx = 2.0 * rgb[3 * i] / 255.0 - 1.0, dy = 2.0 * rgb[3 * i + 1] / 255.0 - 1.0;
    const double s = strength * rgb[3 * i + 2] / 255.0;
    const vec2 spec = specWidths(roughness, s);
    const float u = uv.pixels[3 * i] / 255.0f;
    EXPECT_EQ(uv.pixels[3 * i + 1], 0);  // V
    const float g = m.reflectionGlossiness * gloss.pixels[i] / 255.0f;
    const vec2 fly = flyWidths(g, u, 0.0f);
    EXPECT_NEAR(fly.x, spec.x, 0.02 * spec.x);  // 8-bit U and glossiness
    EXPECT_NEAR(fly.y, spec.y, 0.02 * spec.y);
    if (s == 0.0) {
      EXPECT_EQ(u, 0.0f);
      continue;
    }
    // The long axis, modulo a half turn (the lobe is symmetric under t' → −t').
    const double expected = rotation + std::atan2(dy, dx);
    const double stored = 2.0 * kPi * turns.pixels[i] / 255.0;
    const double diff = std::remainder(stored - expected, kPi);
    EXPECT_LE(std::abs(diff), kPi / 255.0 + 1e-9) << "stored " << stored << ", expected " << expected;
  }
  EXPECT_TRUE(r.warnings.empty()) << r.warnings[0];
}

// A uniform direction texture (AnisotropyRotationTest's 4×4 "30°" image) converts to constants: the rotation
// keeps full precision and no texture is made.
TEST_F(GltfImport, UniformAnisotropyTextureConvertsToConstants) {
  const uint16_t red = 238, green = 191;  // 0.5 + 0.5 (cos 30°, sin 30°), rounded to 8 bits
  std::vector<uint16_t> rgb;
  for (int i = 0; i < 16; ++i) rgb.insert(rgb.end(), {red, green, 255});
  GltfBuilder b = withMaterial(json::object());
  const int tex = addImageTexture(b, test::png(4, 4, rgb));
  b.doc["materials"][0] =
      anisotropic(0.3, {{"anisotropyStrength", 0.5}, {"anisotropyTexture", {{"index", tex}}}});
  import(b);
  const Material& m = onlyMaterialOfMesh();
  EXPECT_FALSE(m.anisotropyTexture || m.anisotropyRotationTexture || m.reflectionGlossinessTexture);
  EXPECT_TRUE(scene_.textures().empty());
  EXPECT_FLOAT_EQ(m.anisotropyRotationRad,
                  float(std::atan2(2.0 * green / 255.0 - 1.0, 2.0 * red / 255.0 - 1.0)));
  EXPECT_NEAR(m.anisotropyRotationRad, kPi / 6.0, degToRad(0.3));
  const vec2 fly = flyWidths(m.reflectionGlossiness, m.anisotropyU, m.anisotropyV);
  EXPECT_NEAR(fly.x, specWidths(0.3, 0.5).x, 1e-6);
  EXPECT_NEAR(fly.y, specWidths(0.3, 0.5).y, 1e-6);
}

// Textured roughness (metallicRoughnessTexture's green) with a constant strength: U and the glossiness vary
// per texel on the roughness texture's grid, and the rotation stays a constant. Texel 0 (roughness 0.2,
// α = 0.04, α_d = 1) is beyond 10:1; texel 1 (roughness 0.8) is exact.
TEST_F(GltfImport, AnisotropyFollowsARoughnessTexture) {
  GltfBuilder b = withMaterial(json::object());
  const int tex = addImageTexture(b, test::png(2, 1, {0, 51, 0, 0, 204, 0}));
  b.doc["materials"][0] = {
      {"pbrMetallicRoughness", {{"metallicRoughnessTexture", {{"index", tex}, {"texCoord", 1}}}}},
      {"extensions",
       {{"KHR_materials_anisotropy", {{"anisotropyStrength", 1.0}, {"anisotropyRotation", 0.3}}}}}};
  const GltfImportResult r = import(b);
  const Material& m = onlyMaterialOfMesh();
  EXPECT_FLOAT_EQ(m.anisotropyRotationRad, 0.3f);
  EXPECT_FALSE(m.anisotropyRotationTexture);
  ASSERT_TRUE(m.anisotropyTexture && m.reflectionGlossinessTexture);
  EXPECT_EQ(m.anisotropyTexture.texCoord, 1);
  EXPECT_EQ(m.reflectionGlossinessTexture.texCoord, 1);
  EXPECT_EQ(scene_.textures().size(), 2u);  // no separate roughness texture
  const Texture& uv = scene_.texture(m.anisotropyTexture.texture);
  const Texture& gloss = scene_.texture(m.reflectionGlossinessTexture.texture);
  const vec2 texel0 =
      flyWidths(m.reflectionGlossiness * gloss.pixels[0] / 255.0f, uv.pixels[0] / 255.0f, 0.0f);
  const vec2 texel1 =
      flyWidths(m.reflectionGlossiness * gloss.pixels[1] / 255.0f, uv.pixels[3] / 255.0f, 0.0f);
  EXPECT_NEAR(texel0.x, 1.0f, 0.01f);
  EXPECT_NEAR(texel0.y, 0.1f, 0.001f);  // α_d / 10, not α = 0.04
  EXPECT_NEAR(texel1.x, 1.0f, 0.01f);
  EXPECT_NEAR(texel1.y, 0.64f, 0.0064f);
  EXPECT_NEAR(m.reflectionGlossiness, std::pow(0.64f, 0.25f), 1e-6f);  // texel 1's, the larger
  EXPECT_TRUE(contains(r.warnings, "more than fly's limit of 10:1 at 1 of 2 texels"))
      << (r.warnings.empty() ? "no warning" : r.warnings[0]);
}

// A width × height RGBA anisotropy texture whose texel (x, y) points at angle(x, y) (radians from the
// tangent): red and green the direction's cosine and sine in [0, 255], blue (strength) and alpha 255.
template <class Angle>
Texture directionTexture(int width, int height, Angle angle) {
  Texture t;
  t.width = width;
  t.height = height;
  t.channels = 4;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const double a = angle(x, y);
      t.pixels.insert(t.pixels.end(), {uint8_t(std::lround(127.5 + 127.5 * std::cos(a))),
                                       uint8_t(std::lround(127.5 + 127.5 * std::sin(a))), 255, 255});
    }
  }
  return t;
}

// The conversion of a material of roughness 0.5 and strength 1 whose directions come from `directions`.
GltfAnisotropyConversion convertDirections(const Texture& directions) {
  GltfAnisotropyInput in;
  in.roughness = 0.5f;
  in.strength = 1.0f;
  in.anisotropyTexture = &directions;
  return convertGltfAnisotropy(in);
}

// The seam of the rotation texture (where the stored angle wraps from 2π to 0) is put where no texel points:
// directions spread over 0°…120° get stored without a jump between neighbours.
TEST(GltfAnisotropyConversion, RotationTextureAvoidsTheWrapWhereTheDirectionsAllow) {
  const Texture directions = directionTexture(13, 1, [](int x, int) { return degToRad(10.0 * x); });
  const GltfAnisotropyConversion c = convertDirections(directions);
  ASSERT_TRUE(c.rotationTexture);
  for (int i = 0; i + 1 < directions.width; ++i) {
    const int step =
        int(c.rotationTexture->pixels[size_t(i) + 1]) - int(c.rotationTexture->pixels[size_t(i)]);
    EXPECT_NEAR(step, 255.0 / 36.0, 1.5) << "texel " << i;  // 10° = 1/36 turn
  }
}

// A disc's directions (AnisotropyDiscTest, AnisotropyBarnLamp: tangential around a centre) turn a full
// circle, so any angle encoding jumps somewhere; stored as the direction's own angle it jumps along one
// radius (about 8 neighbour pairs on a 16 × 16 grid), not along two as modulo a half turn.
TEST(GltfAnisotropyConversion, RotationTextureOfADiscJumpsAlongOneRadius) {
  constexpr int kSize = 16;
  const Texture directions = directionTexture(kSize, kSize, [](int x, int y) {
    return std::atan2(y - 7.5, x - 7.5) + kPi / 2.0;  // tangential
  });
  const GltfAnisotropyConversion c = convertDirections(directions);
  ASSERT_TRUE(c.rotationTexture);
  const std::vector<uint8_t>& red = c.rotationTexture->pixels;
  int jumps = 0;
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      const size_t i = size_t(y * kSize + x);
      if (x + 1 < kSize && std::abs(red[i] - red[i + 1]) > 64) ++jumps;
      if (y + 1 < kSize && std::abs(red[i] - red[i + kSize]) > 64) ++jumps;
      // Every texel still holds its direction, modulo the lobe's half turn.
      const double a = std::atan2(y - 7.5, x - 7.5) + kPi / 2.0;
      EXPECT_LE(std::abs(std::remainder(2.0 * kPi * red[i] / 255.0 - a, kPi)), degToRad(1.5))
          << x << ", " << y;
    }
  }
  EXPECT_GE(jumps, 7);
  EXPECT_LE(jumps, 10);
}

TEST_F(GltfImport, AnisotropyUnderAClearCoatLobeIsDroppedWithAWarning) {
  GltfBuilder b = withMaterial(
      {{"pbrMetallicRoughness", {{"metallicFactor", 0}, {"roughnessFactor", 0.6}}},
       {"extensions",
        {{"KHR_materials_clearcoat", {{"clearcoatFactor", 1.0}, {"clearcoatRoughnessFactor", 0.05}}},
         {"KHR_materials_anisotropy", {{"anisotropyStrength", 0.7}}}}}});
  const GltfImportResult r = import(b);
  EXPECT_FALSE(onlyMaterialOfMesh().isAnisotropic());
  EXPECT_FLOAT_EQ(onlyMaterialOfMesh().reflectionGlossiness, 0.05f);
  EXPECT_TRUE(contains(r.warnings,
                       "its anisotropy (KHR_materials_anisotropy) is dropped: the reflection lobe is "
                       "the clear coat's"));
}

// Bad values are input errors naming the file, the JSON path and the value, and leave the scene unchanged.
TEST_F(GltfImport, BadAnisotropyValuesAreInputErrors) {
  const std::string ext = "/materials/0/extensions/KHR_materials_anisotropy";
  struct Case {
    json extension;
    std::string path, text;
  };
  const std::vector<Case> cases = {
      {{{"anisotropyStrength", 1.5}},
       ext + "/anisotropyStrength",
       "material 0 anisotropyStrength is 1.5; glTF requires a value in [0, 1]"},
      {{{"anisotropyStrength", -0.25}},
       ext + "/anisotropyStrength",
       "material 0 anisotropyStrength is -0.25; glTF requires a value in [0, 1]"},
      {{{"anisotropyStrength", "strong"}},
       ext + "/anisotropyStrength",
       "'anisotropyStrength' must be a number"},
      {{{"anisotropyStrength", 0.5}, {"anisotropyRotation", "left"}},
       ext + "/anisotropyRotation",
       "'anisotropyRotation' must be a number"},
      {{{"anisotropyStrength", 0.5}, {"anisotropyTexture", {{"index", 3}}}},
       ext + "/anisotropyTexture/index",
       "material 0 anisotropyTexture refers to texture 3, but the file has 1 textures"},
      {{{"anisotropyStrength", 0.5}, {"anisotropyTexture", {{"texCoord", 0}}}},
       ext + "/anisotropyTexture",
       "'anisotropyTexture' needs an 'index'"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.text);
    GltfBuilder b = withMaterial(anisotropic(0.5, c.extension));
    addImageTexture(b, test::png(1, 1, {255, 128, 255}));
    const std::filesystem::path file = dir_ / "bad.gltf";
    b.writeGltf(file);
    try {
      importGltf(scene_, file);
      ADD_FAILURE() << "no InputError";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(c.text), std::string::npos) << e.what();
      EXPECT_EQ(e.location().file, file.string());
      EXPECT_EQ(e.location().jsonPath, c.path);
      EXPECT_FALSE(e.hint().empty());
    }
    EXPECT_TRUE(scene_.materials().empty() && scene_.meshes().empty() && scene_.textures().empty());
  }
  // A non-finite rotation cannot be written in JSON: 1e999 overflows, and the file is refused as it is read.
  GltfBuilder b =
      withMaterial(anisotropic(0.5, {{"anisotropyStrength", 0.5}, {"anisotropyRotation", 12345.678}}));
  const std::filesystem::path file = dir_ / "overflow.gltf";
  b.writeGltf(file);
  std::ifstream in(file);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  text.replace(text.find("12345.678"), 9, "1e999");
  test::writeText(file, text);
  try {
    importGltf(scene_, file);
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(file.string() + ": cannot read the glTF file"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("number overflow parsing '1e999'"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(scene_.materials().empty());
}

// A finite rotation of any size is an angle: it is taken modulo a full turn.
TEST_F(GltfImport, AnisotropyRotationIsTakenModuloAFullTurn) {
  GltfBuilder b =
      withMaterial(anisotropic(0.5, {{"anisotropyStrength", 0.5}, {"anisotropyRotation", 1e300}}));
  import(b);
  const float rotation = onlyMaterialOfMesh().anisotropyRotationRad;
  EXPECT_TRUE(std::isfinite(rotation));
  EXPECT_NEAR(rotation, std::remainder(1e300, 2.0 * kPi), 1e-6);
}

}  // namespace
}  // namespace fly::sdb
