// PNG text chunks and print resolution written into an encoded PNG and read back; the image still decodes.
#include "base/png_metadata.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "base/file_io.h"
#include "base/image_io.h"

namespace fly {
namespace {

namespace fs = std::filesystem;

TEST(PngMetadata, TextAndResolutionReadBackAndTheImageDecodes) {
  const fs::path path = fs::temp_directory_path() / "fly_png_metadata_test.png";
  const std::vector<uint8_t> pixels = {255, 0, 0, 0, 255, 0, 0, 0, 255, 9, 9, 9};
  PngMetadata m;
  m.text = {{"Title", "Plan"},
            {"fly:command", "fly illuminance house.json --grid 0.85,0.5 --image 'a b.png'"},
            {"fly:site", "latitude 60.1700°, longitude 24.9400°"}};  // UTF-8: an iTXt chunk
  m.dotsPerInch = 300.0;
  writePng(path, 2, 2, 3, pixels.data(), m);
  const std::string bytes = readInputFile(path, "PNG");
  const PngMetadata back = readPngMetadata(bytes);
  ASSERT_EQ(back.text.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(back.text[i].first, m.text[i].first);
    EXPECT_EQ(back.text[i].second, m.text[i].second);
  }
  // pHYs holds round(300 / 0.0254) = 11811 pixels per metre: 299.9994 dpi.
  EXPECT_NEAR(back.dotsPerInch, 11811 * 0.0254, 1e-9);
  EXPECT_NE(bytes.find("tEXtTitle"), std::string::npos);
  EXPECT_NE(bytes.find("iTXtfly:site"), std::string::npos);
  const ImageU8 image = readPng(path);
  EXPECT_EQ(image.width, 2);
  EXPECT_EQ(image.pixels, pixels);
  fs::remove(path);
}

TEST(PngMetadata, BadInputIsRejectedAndBadChunksSkipped) {
  const fs::path path = fs::temp_directory_path() / "fly_png_metadata_bad.png";
  const std::vector<uint8_t> pixels = {1, 2, 3};
  writePng(path, 1, 1, 3, pixels.data(), {{{"Comment", "kept"}, {"Author", "corrupted"}}, 0.0});
  std::string bytes = readInputFile(path, "PNG");
  fs::remove(path);
  EXPECT_THROW(withPngMetadata("not a png", {}), std::invalid_argument);
  EXPECT_THROW(withPngMetadata(bytes, {{{"", "empty keyword"}}, 0.0}), std::invalid_argument);
  EXPECT_THROW(withPngMetadata(bytes, {{{"a  b", "double space"}}, 0.0}), std::invalid_argument);
  EXPECT_THROW(withPngMetadata(bytes, {{}, -1.0}), std::invalid_argument);
  EXPECT_THROW(readPngMetadata(bytes.substr(0, bytes.size() - 6)), std::invalid_argument);
  // A flipped byte in the second chunk's text: its CRC fails and it is skipped.
  const size_t at = bytes.find("corrupted");
  ASSERT_NE(at, std::string::npos);
  bytes[at] = 'C';
  const PngMetadata back = readPngMetadata(bytes);
  ASSERT_EQ(back.text.size(), 1u);
  EXPECT_EQ(back.text[0].second, "kept");
  EXPECT_EQ(back.dotsPerInch, 0.0);
}

}  // namespace
}  // namespace fly
