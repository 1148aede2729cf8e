// glTF material extensions (clear coat, sheen, variants), the messages for extensions fly does not convert,
// KTX2 textures and the import budget.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cstring>

#include "base/file_io.h"
#include "gltf_import_fixture.h"
#include "sdb/material_layers.h"

namespace fly::sdb {
namespace {

using json = nlohmann::json;
using test::GltfBuilder;

TEST_F(GltfImport, ClearcoatOverADielectricIsTheReflectionLobe) {
  GltfBuilder b = withMaterial(
      {{"pbrMetallicRoughness",
        {{"baseColorFactor", {0.6, 0.1, 0.1, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 0.7}}},
       {"extensions",
        {{"KHR_materials_clearcoat", {{"clearcoatFactor", 1.0}, {"clearcoatRoughnessFactor", 0.08}}}}}});
  b.useExtension("KHR_materials_clearcoat", true);  // ClearCoatCarPaint requires it
  import(b);
  const Material& m = onlyMaterialOfMesh();
  EXPECT_EQ(m.reflectionModel, ReflectionModel::kFresnel);
  EXPECT_FLOAT_EQ(m.ior, 1.5f);
  EXPECT_FLOAT_EQ(m.reflectionGlossiness, 0.08f);
  expectRgb(m.reflectionColor, Rgb(1.0f));
  expectRgb(m.diffuseColor, Rgb(0.6f, 0.1f, 0.1f));
}

TEST_F(GltfImport, ClearcoatOverAMetalKeepsTheMetalsColourAsDiffuse) {
  GltfBuilder b = withMaterial(
      {{"pbrMetallicRoughness",
        {{"baseColorFactor", {0.5, 0.05, 0.02, 1}}, {"metallicFactor", 1}, {"roughnessFactor", 0.45}}},
       {"extensions",
        {{"KHR_materials_clearcoat", {{"clearcoatFactor", 0.8}, {"clearcoatRoughnessFactor", 0.02}}}}}});
  import(b);
  const Material& m = onlyMaterialOfMesh();
  EXPECT_EQ(m.reflectionModel, ReflectionModel::kFresnel);
  expectRgb(m.reflectionColor, Rgb(0.8f));
  EXPECT_FLOAT_EQ(m.reflectionGlossiness, 0.02f);
  expectRgb(m.diffuseColor, Rgb(0.5f, 0.05f, 0.02f));  // metallic 1: reflectance = baseColor
  // Total albedo at normal incidence, as glTF layers it: 0.8·0.04 + (1 − 0.8·0.04)·baseColor.
  const EffectiveComponents e = m.effective();
  EXPECT_NEAR(e.reflection.r + e.diffuse.r, 0.032f + 0.968f * 0.5f, 1e-6f);
}

TEST_F(GltfImport, ClearcoatTexturesTakeTheReflectionSlots) {
  GltfBuilder b = withMaterial(json::object());
  const int tex = addImageTexture(b, test::png(2, 1, {10, 20, 30, 40, 50, 60}));
  const int rough = addImageTexture(b, test::png(2, 1, {1, 2, 3, 4, 5, 6}));
  b.doc["materials"][0] = {
      {"pbrMetallicRoughness", {{"metallicFactor", 0}, {"metallicRoughnessTexture", {{"index", rough}}}}},
      {"extensions",
       {{"KHR_materials_clearcoat",
         {{"clearcoatFactor", 1.0},
          {"clearcoatTexture", {{"index", tex}}},
          {"clearcoatRoughnessTexture", {{"index", tex}}},
          {"clearcoatNormalTexture", {{"index", tex}}}}}}}};
  const GltfImportResult r = import(b);
  const Material& m = onlyMaterialOfMesh();
  ASSERT_TRUE(m.reflectionTexture);
  EXPECT_EQ(scene_.texture(m.reflectionTexture.texture).pixels, (std::vector<uint8_t>{10, 40}));  // red
  ASSERT_TRUE(m.reflectionGlossinessTexture);
  EXPECT_EQ(scene_.texture(m.reflectionGlossinessTexture.texture).pixels, (std::vector<uint8_t>{20, 50}));
  // The base's roughness texture belongs to the lobe the coat replaced; it is not imported.
  EXPECT_EQ(scene_.textures().size(), 2u);
  EXPECT_TRUE(contains(r.warnings, "clearcoatNormalTexture is not imported"));
}

TEST_F(GltfImport, ClearcoatUnderAShinierMetalIsDroppedWithAWarning) {
  GltfBuilder b = withMaterial(
      {{"pbrMetallicRoughness", {{"metallicFactor", 1}, {"roughnessFactor", 0.05}}},
       {"extensions",
        {{"KHR_materials_clearcoat", {{"clearcoatFactor", 1.0}, {"clearcoatRoughnessFactor", 0.3}}}}}});
  const GltfImportResult r = import(b);
  EXPECT_EQ(onlyMaterialOfMesh().reflectionModel, ReflectionModel::kUniform);
  EXPECT_TRUE(contains(r.warnings, "its clear coat is dropped"));
  b.doc["materials"][0]["extensions"]["KHR_materials_clearcoat"]["clearcoatFactor"] = 1.5;
  EXPECT_NE(importError(b).find("clearcoatFactor is 1.5; glTF requires a value in [0, 1]"),
            std::string::npos);
}

TEST_F(GltfImport, SheenIsFoldedIntoTheDiffuseColour) {
  GltfBuilder b = withMaterial(
      {{"pbrMetallicRoughness",
        {{"baseColorFactor", {0.2, 0.3, 0.4, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 0.8}}},
       {"extensions",
        {{"KHR_materials_sheen",
          {{"sheenColorFactor", {1.0, 0.329, 0.1}},
           {"sheenRoughnessFactor", 0.8},
           {"sheenColorTexture", {{"index", 0}}}}}}}});
  b.useExtension("KHR_materials_sheen", true);
  // Two texels, sRGB (255, 128, 0) and (0, 128, 255): mean linear colour (½, srgb(128/255), ½).
  addImageTexture(b, test::png(2, 1, {255, 128, 0, 0, 128, 255}));
  const GltfImportResult r = import(b);
  const float e = sheenAlbedo(0.8f);
  const Rgb meanTexel(0.5f, srgbToLinear(128.0f / 255.0f), 0.5f);
  const Rgb sheen = Rgb(1.0f, 0.329f, 0.1f) * meanTexel;  // max 0.5
  expectRgb(onlyMaterialOfMesh().diffuseColor, Rgb(0.2f, 0.3f, 0.4f) * (1.0f - 0.5f * e) + sheen * e, 1e-6f);
  EXPECT_TRUE(contains(r.warnings, "the textures of KHR_materials_sheen are applied as their mean"));
  EXPECT_TRUE(scene_.textures().empty());  // averaged, not sampled
  b.doc["materials"][0]["extensions"]["KHR_materials_sheen"]["sheenRoughnessTexture"] = {{"index", 4}};
  EXPECT_NE(importError(b).find("refers to texture 4, but the file has 1 textures"), std::string::npos);
}

TEST_F(GltfImport, SpecularTexturesScaleTheFactorsByTheirMeans) {
  GltfBuilder b = withMaterial(
      {{"pbrMetallicRoughness", {{"metallicFactor", 0}, {"roughnessFactor", 0.5}}},
       {"extensions",
        {{"KHR_materials_specular",
          {{"specularFactor", 0.5},
           {"specularColorFactor", {1.0, 0.8, 0.6}},
           {"specularTexture", {{"index", 0}}},
           {"specularColorTexture", {{"index", 0}}}}}}}});
  // specularTexture reads alpha (1 in an RGB image); specularColorTexture the sRGB colour.
  addImageTexture(b, test::png(2, 1, {255, 128, 0, 0, 128, 255}));
  const GltfImportResult r = import(b);
  const Rgb meanTexel(0.5f, srgbToLinear(128.0f / 255.0f), 0.5f);
  expectRgb(onlyMaterialOfMesh().reflectionColor, Rgb(1.0f, 0.8f, 0.6f) * meanTexel * 0.5f, 1e-6f);
  EXPECT_TRUE(contains(r.warnings, "the textures of KHR_materials_specular are applied as their mean"));
}

TEST_F(GltfImport, VariantsImportTheDefaultMaterialsAndAreListed) {
  GltfBuilder b = withMaterial(
      {{"name", "Default"}, {"pbrMetallicRoughness", {{"baseColorFactor", {0.1, 0.2, 0.3, 1}}}}});
  b.material({{"name", "Velvet"}, {"pbrMetallicRoughness", {{"baseColorFactor", {0.9, 0.1, 0.1, 1}}}}});
  b.doc["meshes"][0]["primitives"][0]["extensions"] = {
      {"KHR_materials_variants", {{"mappings", json::array({{{"material", 1}, {"variants", {0}}}})}}}};
  b.doc["extensions"] = {{"KHR_materials_variants",
                          {{"variants", json::array({{{"name", "Mango Velvet"}}, {{"name", "Peacock"}}})}}}};
  b.useExtension("KHR_materials_variants", true);
  const GltfImportResult r = import(b);
  EXPECT_EQ(onlyMaterialOfMesh().name, "Default");
  EXPECT_TRUE(contains(r.warnings,
                       "material variants (KHR_materials_variants) 'Mango Velvet', 'Peacock'; the "
                       "default materials are imported"));
}

TEST_F(GltfImport, UnlitAndUnknownExtensionsSayWhatIsLost) {
  GltfBuilder b = withMaterial(json::object());
  b.useExtension("KHR_materials_unlit");
  b.useExtension("EXT_made_up");
  const GltfImportResult r = import(b);
  EXPECT_TRUE(
      contains(r.warnings, "'KHR_materials_unlit' is not supported: unlit materials are shaded as lit"));
  EXPECT_TRUE(contains(r.warnings, "'EXT_made_up' is not supported: what it adds is ignored"));
  b.useExtension("EXT_made_up", true);
  const std::string error = importError(b);
  EXPECT_NE(error.find("requires the glTF extension 'EXT_made_up'"), std::string::npos);
  EXPECT_NE(error.find("docs/scene-format.md lists the extensions fly reads"), std::string::npos) << error;
  EXPECT_EQ(error.find("compression"), std::string::npos) << error;
}

TEST_F(GltfImport, Ktx2TextureIsAnInputErrorNamingTheFileAndTheExtension) {
  const uint8_t ktx2[] = {0xab, 'K', 'T', 'X', ' ', '2', '0', 0xbb, '\r', '\n', 0x1a, '\n', 0, 0, 0, 0};
  test::writeBytes(dir_ / "lamp_normal.ktx2", ktx2, sizeof(ktx2));
  GltfBuilder b = withMaterial(json::object());
  b.append("images", {{"uri", "lamp_normal.ktx2"}});
  b.append("textures", {{"source", 0}});
  b.doc["materials"][0] = {{"normalTexture", {{"index", 0}}}};
  const std::string error = importError(b);
  EXPECT_NE(error.find((dir_ / "lamp_normal.ktx2").string() + "' is a KTX2 (Basis Universal) texture"),
            std::string::npos)
      << error;
  EXPECT_NE(error.find("KHR_texture_basisu"), std::string::npos);
  EXPECT_NE(error.find("ktx extract lamp_normal.ktx2 OUT.png"), std::string::npos) << error;
}

// --- The import budget (GltfImportOptions::maxDecodedBytes, kMaxTextureDimension).

TEST_F(GltfImport, AccessorClaimingTwoToThe31VerticesFailsBeforeAllocating) {
  GltfBuilder b;
  b.triangles(kTriangle, {}, "Huge");
  b.doc["accessors"][0]["count"] = uint64_t(1) << 31;  // 2³¹ VEC3 floats: 24 GiB as stored, 48 GiB as doubles
  b.node({{"mesh", 0}});
  b.scene({0});
  const std::string error = importError(b);
  EXPECT_NE(error.find("accessor 0 (POSITION of mesh 'Huge' primitive 0), 2147483648 elements of VEC3, would "
                       "take 24 GiB decoded, more than the 4 GiB left of fly's import budget"),
            std::string::npos)
      << error;
  EXPECT_NE(error.find("/accessors/0/count"), std::string::npos) << error;
  EXPECT_TRUE(scene_.meshes().empty());
}

TEST_F(GltfImport, BudgetCoversEveryAccessorOfTheFile) {
  GltfBuilder b;
  b.triangles(kTriangle, {0, 1, 2}, "Small");
  b.node({{"mesh", 0}});
  b.scene({0});
  GltfImportOptions options;
  options.maxDecodedBytes = 3 * 3 * 4 + 3 * 4;  // exactly the positions and the indices
  EXPECT_NO_THROW(import(b, options));
  options.maxDecodedBytes -= 1;
  try {
    import(b, options);
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("indices of mesh 'Small' primitive 0"), std::string::npos)
        << e.what();
  }
}

TEST_F(GltfImport, TextureClaiming100000SquaredPixelsFailsBeforeDecoding) {
  // A PNG whose header declares 100 000 × 100 000 px and whose data holds 1 row: decoding it would allocate
  // 40 GB before noticing.
  std::vector<uint8_t> image = test::png(1, 1, {1, 2, 3});
  const uint32_t side = 100000;
  for (int k = 0; k < 4; ++k) image[16 + k] = image[20 + k] = uint8_t(side >> (24 - 8 * k));
  GltfBuilder b = withMaterial(json::object());
  const int tex = addImageTexture(b, image);
  b.doc["materials"][0] = {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", tex}}}}}};
  const std::string error = importError(b);
  EXPECT_NE(error.find("is 100000 × 100000 px; fly imports textures of at most 16384 px a side"),
            std::string::npos)
      << error;
  // Within the side limit but over the budget: 16384² RGBA = 1 GiB against a budget of 64 MiB.
  for (int k = 0; k < 4; ++k) image[16 + k] = image[20 + k] = uint8_t(uint32_t(16384) >> (24 - 8 * k));
  GltfBuilder c = withMaterial(json::object());
  addImageTexture(c, image);
  c.doc["materials"][0] = {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}};
  c.writeGltf(dir_ / "big.gltf");
  GltfImportOptions options;
  options.maxDecodedBytes = uint64_t(64) << 20;
  try {
    importGltf(scene_, dir_ / "big.gltf", options);
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("would take 1 GiB decoded, more than the 64 MiB left"),
              std::string::npos)
        << e.what();
  }
}

// A 16384² PNG (1 GiB decoded, within the default budget) whose file holds a 1 × 1 image: no complete PNG of
// that size is smaller than 16384 · (1 + 16384 · 3) / 1032 bytes (deflate's largest ratio), so it fails before
// its pixels are allocated. A real PNG of 2048² black pixels, which deflate compresses close to that limit
// (OpenImageIO's writer, zlib level 9), still imports.
TEST_F(GltfImport, ImageFileTooSmallForItsDeclaredSizeFailsBeforeDecoding) {
  std::vector<uint8_t> image = test::png(1, 1, {1, 2, 3});
  for (int k = 0; k < 4; ++k) image[16 + k] = image[20 + k] = uint8_t(uint32_t(16384) >> (24 - 8 * k));
  GltfBuilder b = withMaterial(json::object());
  addImageTexture(b, image);
  b.doc["materials"][0] = {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}};
  const std::string error = importError(b);
  const uint64_t least = uint64_t(16384) * (1 + 16384 * 3) / 1032;
  EXPECT_NE(error.find("declares 16384 × 16384 px, which no complete image of its format stores in fewer than " +
                       std::to_string(least) + " bytes; it has " + std::to_string(image.size())),
            std::string::npos)
      << error;

  const std::filesystem::path flatFile = dir_ / "flat.png";
  {
    auto out = OIIO::ImageOutput::create(flatFile.string());
    ASSERT_TRUE(out);
    OIIO::ImageSpec spec(2048, 2048, 3, OIIO::TypeDesc::UINT8);
    spec.attribute("png:compressionLevel", 9);
    ASSERT_TRUE(out->open(flatFile.string(), spec));
    const std::vector<uint8_t> black(size_t(2048) * 2048 * 3, 0);
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, black.data()));
    ASSERT_TRUE(out->close());
  }
  const std::string flatBytes = readInputFile(flatFile, "test image");
  const std::vector<uint8_t> flat(flatBytes.begin(), flatBytes.end());
  EXPECT_LT(flat.size(), size_t(2048) * (1 + 2048 * 3) / 1000);  // within 3 % of the limit
  GltfBuilder c = withMaterial(json::object());
  addImageTexture(c, flat);
  c.doc["materials"][0] = {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}};
  EXPECT_EQ(importError(c), "");
}

TEST_F(GltfImport, JpegHeaderSizeIsCheckedBeforeDecoding) {
  // SOI, an APP0 segment, then SOF0 declaring 20000 × 30 px (ITU-T T.81 §B.2.2); no scan follows.
  const std::vector<uint8_t> jpeg = {0xff,
                                     0xd8,
                                     0xff,
                                     0xe0,
                                     0,
                                     4,
                                     0,
                                     0,
                                     0xff,
                                     0xc0,
                                     0,
                                     11,
                                     8,
                                     0,
                                     30,
                                     uint8_t(20000 >> 8),
                                     uint8_t(20000 & 0xff),
                                     1,
                                     1,
                                     0x11,
                                     0};
  GltfBuilder b = withMaterial(json::object());
  const int view = b.view(jpeg);
  b.append("images", {{"bufferView", view}, {"mimeType", "image/jpeg"}});
  b.append("textures", {{"source", 0}});
  b.doc["materials"][0] = {{"emissiveTexture", {{"index", 0}}}};
  EXPECT_NE(importError(b).find("is 20000 × 30 px; fly imports textures of at most 16384 px a side"),
            std::string::npos);
}

}  // namespace
}  // namespace fly::sdb
