// Texture images through the OpenImageIO decoder (oiio_image_decoder.h) that the fly program installs: float
// images clamped to 16 bits, grey images expanded to RGBA, colour kept unmultiplied by alpha, WebP textures (EXT_texture_webp), and what the
// default decoder (stb_image, PNG and JPEG only) says about other formats.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cstring>
#include <fstream>
#include <iterator>

#include "gltf_import_fixture.h"
#include "sdb/oiio_image_decoder.h"

namespace fly::sdb {
namespace {

using json = nlohmann::json;
using test::GltfBuilder;

// Installs OpenImageIO's decoder for one test and restores the default afterwards.
class GltfImagesOiio : public GltfImport {
 protected:
  void SetUp() override {
    GltfImport::SetUp();
    setImageDecoder(&decodeImageOiio);
  }
  void TearDown() override {
    setImageDecoder({});
    GltfImport::TearDown();
  }
};

// Colour written as given (unassociated alpha), as a PNG file stores it.
void writeImage(const std::filesystem::path& file, int width, int height, int channels, OIIO::TypeDesc type,
                const void* pixels) {
  auto out = OIIO::ImageOutput::create(file.string());
  ASSERT_TRUE(out) << OIIO::geterror();
  OIIO::ImageSpec spec(width, height, channels, type);
  spec.attribute("oiio:UnassociatedAlpha", 1);
  ASSERT_TRUE(out->open(file.string(), spec)) << out->geterror();
  ASSERT_TRUE(out->write_image(type, pixels)) << out->geterror();
  out->close();
}

GltfBuilder withBaseColorImage(const std::string& uri) {
  GltfBuilder b = withMaterial(json::object());
  b.append("images", {{"uri", uri}});
  b.append("textures", {{"source", 0}});
  b.doc["materials"][0] = {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}};
  return b;
}

std::vector<uint16_t> samples16(const Texture& t) {
  std::vector<uint16_t> v(t.pixels.size() / 2);
  std::memcpy(v.data(), t.pixels.data(), t.pixels.size());
  return v;
}

TEST_F(GltfImagesOiio, FloatExrIsClampedToSixteenBitsWithAWarning) {
  const float rgb[] = {0.5f, 2.0f, -1.0f, 0.25f, 0.75f, 1.0f};
  writeImage(dir_ / "sky.exr", 2, 1, 3, OIIO::TypeDesc::FLOAT, rgb);
  const GltfImportResult r = import(withBaseColorImage("sky.exr"));
  const Texture& t = scene_.texture(onlyMaterialOfMesh().diffuseTexture.texture);
  EXPECT_EQ(t.width, 2);
  EXPECT_EQ(t.channels, 4);
  EXPECT_EQ(t.bitsPerChannel, 16);
  // round(v · 65535) after clamping to [0, 1]; alpha 1.
  EXPECT_EQ(samples16(t), (std::vector<uint16_t>{32768, 65535, 0, 65535, 16384, 49151, 65535, 65535}));
  EXPECT_TRUE(
      contains(r.warnings, "2 of its 6 float values lie outside [0, 1] (the largest is 2) and were clamped"));
}

TEST_F(GltfImagesOiio, GreyPngIsExpandedToRgba) {
  const uint16_t grey[] = {0, 1000, 65535};
  writeImage(dir_ / "rough.png", 3, 1, 1, OIIO::TypeDesc::UINT16, grey);
  import(withBaseColorImage("rough.png"));
  const Texture& t = scene_.texture(onlyMaterialOfMesh().diffuseTexture.texture);
  EXPECT_EQ(t.bitsPerChannel, 16);
  EXPECT_EQ(samples16(t),
            (std::vector<uint16_t>{0, 0, 0, 65535, 1000, 1000, 1000, 65535, 65535, 65535, 65535, 65535}));
}

// A PNG's colour is kept as stored where its alpha is below 1 (unassociated, as glTF means it), not
// multiplied by alpha on decoding: an OPAQUE material over such an image shows the colour, not black.
TEST_F(GltfImagesOiio, PngWithAlphaKeepsItsColourUnmultiplied) {
  const uint8_t rgba[] = {200, 100, 50, 128, 10, 20, 30, 0};
  writeImage(dir_ / "label.png", 2, 1, 4, OIIO::TypeDesc::UINT8, rgba);
  import(withBaseColorImage("label.png"));
  const Texture& t = scene_.texture(onlyMaterialOfMesh().diffuseTexture.texture);
  EXPECT_EQ(t.bitsPerChannel, 8);
  EXPECT_EQ(t.pixels, (std::vector<uint8_t>{200, 100, 50, 128, 10, 20, 30, 0}));
}

TEST_F(GltfImagesOiio, WebpSourceReplacesTheFallbackImage) {
  std::vector<uint8_t> webp(3 * 2 * 3, 200);
  writeImage(dir_ / "wood.webp", 3, 2, 3, OIIO::TypeDesc::UINT8, webp.data());
  const std::vector<uint8_t> fallback = test::png(1, 1, {1, 2, 3});
  test::writeBytes(dir_ / "wood.png", fallback.data(), fallback.size());
  GltfBuilder b = withMaterial(json::object());
  b.append("images", {{"uri", "wood.png"}});
  b.append("images", {{"uri", "wood.webp"}});
  b.append("textures", {{"source", 0}, {"extensions", {{"EXT_texture_webp", {{"source", 1}}}}}});
  b.doc["materials"][0] = {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}};
  b.useExtension("EXT_texture_webp");
  import(b);
  const Texture& t = scene_.texture(onlyMaterialOfMesh().diffuseTexture.texture);
  EXPECT_EQ(t.width, 3);
  EXPECT_EQ(t.height, 2);
  EXPECT_EQ(t.bitsPerChannel, 8);
  EXPECT_NEAR(t.pixels[0], 200, 3);  // lossy WebP
}

TEST_F(GltfImagesOiio, DecoderChecksTheBudgetBeforeDecoding) {
  const float rgb[] = {0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f};
  writeImage(dir_ / "big.exr", 2, 1, 3, OIIO::TypeDesc::HALF, rgb);
  std::vector<std::string> notes;
  std::ifstream in(dir_ / "big.exr", std::ios::binary);
  const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // 2 × 1 px RGBA at 16 bits = 16 bytes.
  EXPECT_EQ(decodeImageOiio(bytes, 16, notes).pixels.size(), 16u);
  try {
    decodeImageOiio(bytes, 15, notes);
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("it is 2 × 1 px, over the import budget"), std::string::npos)
        << e.what();
  }
}

TEST_F(GltfImport, WithoutADecoderOtherFormatsAreInputErrorsWithAHint) {
  const float rgb[] = {0.5f, 0.5f, 0.5f};
  writeImage(dir_ / "sky.exr", 1, 1, 3, OIIO::TypeDesc::FLOAT, rgb);
  const std::string error = importError(withBaseColorImage("sky.exr"));
  EXPECT_NE(
      error.find("sky.exr' is an OpenEXR image; without an image decoder installed fly reads PNG and JPEG"),
      std::string::npos)
      << error;
  EXPECT_NE(error.find("use the fly program, which decodes WebP, HDR, EXR and TIFF"), std::string::npos);
}

}  // namespace
}  // namespace fly::sdb
