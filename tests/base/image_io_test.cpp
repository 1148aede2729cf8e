#include "base/image_io.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include "base/error.h"
#include "base/file_io.h"

namespace fly {
namespace {

namespace fs = std::filesystem;

class ImageIoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("fly_image_io_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  size_t filesInDir() const {
    size_t n = 0;
    for (const auto& e : fs::directory_iterator(dir_)) n += e.is_regular_file() ? 1 : 0;
    return n;
  }

  fs::path dir_;
};

// Luminances from 1e-6 cd/m² (starlit ground) to 1e9 cd/m² (the sun's disc is about 1.6e9), spread evenly in
// log scale: most are not representable in half precision, and half's range ends at 65504, so any conversion
// to half would show.
ImageRgbF wideRangeImage() {
  ImageRgbF image;
  image.width = 5;
  image.height = 7;  // 35 pixels, 105 values
  for (int i = 0; i < 3 * image.width * image.height; ++i) {
    const double decade = -6.0 + 15.0 * i / (3.0 * image.width * image.height - 1.0);
    image.rgb.push_back(static_cast<float>(std::pow(10.0, decade)));
  }
  return image;
}

TEST_F(ImageIoTest, ExrRoundTripIsBitExactFromMicroToGigaCandela) {
  const ImageRgbF image = wideRangeImage();
  EXPECT_FLOAT_EQ(image.rgb.front(), 1e-6f);
  EXPECT_FLOAT_EQ(image.rgb.back(), 1e9f);
  const fs::path p = dir_ / "sky.exr";
  writeExr(p, image);
  const ImageRgbF back = readExr(p);
  EXPECT_EQ(back.width, image.width);
  EXPECT_EQ(back.height, image.height);
  EXPECT_EQ(back.rgb, image.rgb);
}

TEST_F(ImageIoTest, ExrPixelOrderIsRowMajorFromTheTop) {
  ImageRgbF image{2, 2, {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12}};
  const fs::path p = dir_ / "order.exr";
  writeExr(p, image);
  EXPECT_EQ(readExr(p).rgb, image.rgb);
}

TEST_F(ImageIoTest, ExrStringAttributesRoundTrip) {
  const fs::path p = dir_ / "sky.exr";
  const ExrAttributes attributes = {{"units", "cd/m^2"}, {"fly:sky", "cie:12 zenith 8000 cd/m^2"}};
  writeExr(p, ImageRgbF{1, 1, {1, 2, 3}}, attributes);
  ExrAttributes back;
  readExr(p, &back);
  for (const auto& a : attributes) {
    EXPECT_NE(std::find(back.begin(), back.end(), a), back.end()) << a.first;
  }
}

TEST_F(ImageIoTest, ExrAttributeNamedLikeAHeaderFieldIsRejected) {
  EXPECT_THROW(writeExr(dir_ / "a.exr", ImageRgbF{1, 1, {1, 2, 3}}, {{"channels", "x"}}),
               std::invalid_argument);
  EXPECT_THROW(writeExr(dir_ / "a.exr", ImageRgbF{1, 1, {1, 2, 3}}, {{"", "x"}}), std::invalid_argument);
  EXPECT_EQ(filesInDir(), 0u);
}

TEST_F(ImageIoTest, NonFiniteValuesAreRejectedAndNothingIsWritten) {
  for (const float v : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                        -std::numeric_limits<float>::infinity()}) {
    ImageRgbF image{2, 1, {0, 0, 0, 1, v, 1}};
    try {
      writeExr(dir_ / "bad.exr", image);
      ADD_FAILURE() << "no exception for " << v;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("pixel (1, 0)"), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(filesInDir(), 0u);
}

TEST_F(ImageIoTest, WrongSizesAreRejected) {
  EXPECT_THROW(writeExr(dir_ / "a.exr", ImageRgbF{}), std::invalid_argument);
  EXPECT_THROW(writeExr(dir_ / "a.exr", ImageRgbF{2, 2, {1, 2, 3}}), std::invalid_argument);
  const uint8_t px[4] = {};
  EXPECT_THROW(writePng(dir_ / "a.png", 1, 1, 5, px), std::invalid_argument);
  EXPECT_THROW(writePng(dir_ / "a.png", 0, 1, 3, px), std::invalid_argument);
  EXPECT_THROW(writePng(dir_ / "a.png", 1, 1, 3, nullptr), std::invalid_argument);
  EXPECT_EQ(filesInDir(), 0u);
}

TEST_F(ImageIoTest, WritesAreAtomicAndLeaveNoTemporaryFile) {
  const fs::path p = dir_ / "sky.exr";
  writeExr(p, ImageRgbF{1, 1, {1, 2, 3}});
  writeExr(p, ImageRgbF{1, 1, {4, 5, 6}});
  EXPECT_EQ(readExr(p).rgb, (std::vector<float>{4, 5, 6}));
  const uint8_t px[3] = {7, 8, 9};
  writePng(dir_ / "a.png", 1, 1, 3, px);
  EXPECT_EQ(filesInDir(), 2u);
}

TEST_F(ImageIoTest, FailedWriteNamesThePathAndKeepsTheOldFile) {
  const fs::path p = dir_ / "sky.exr";
  writeExr(p, ImageRgbF{1, 1, {1, 2, 3}});
  const fs::path impossible = dir_ / "missing-dir" / "sky.exr";
  try {
    writeExr(impossible, ImageRgbF{1, 1, {4, 5, 6}});
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(impossible.string()), std::string::npos) << e.what();
  }
  const uint8_t px[3] = {};
  EXPECT_THROW(writePng(impossible.parent_path() / "a.png", 1, 1, 3, px), std::runtime_error);
  EXPECT_EQ(readExr(p).rgb, (std::vector<float>{1, 2, 3}));
  EXPECT_EQ(filesInDir(), 1u);
  EXPECT_FALSE(fs::exists(impossible.parent_path()));
}

TEST_F(ImageIoTest, PngRoundTripForEveryChannelCount) {
  for (int channels = 1; channels <= 4; ++channels) {
    const int width = 5, height = 3;
    std::vector<uint8_t> pixels;
    for (int i = 0; i < width * height * channels; ++i) pixels.push_back(static_cast<uint8_t>(i * 37 % 256));
    const fs::path p = dir_ / ("c" + std::to_string(channels) + ".png");
    writePng(p, width, height, channels, pixels.data());
    const ImageU8 back = readPng(p);
    EXPECT_EQ(back.width, width);
    EXPECT_EQ(back.height, height);
    EXPECT_EQ(back.channels, channels);
    EXPECT_EQ(back.pixels, pixels) << channels << " channels";
  }
}

TEST_F(ImageIoTest, MissingAndCorruptFilesAreInputErrorsNamingThePath) {
  const fs::path missing = dir_ / "none.exr";
  EXPECT_THROW(readExr(missing), InputError);
  EXPECT_THROW(readPng(dir_ / "none.png"), InputError);

  // A valid file cut in half, and text with an image's name.
  const fs::path exr = dir_ / "sky.exr";
  writeExr(exr, wideRangeImage());
  const std::string bytes = readInputFile(exr, "test");
  writeFileAtomic(exr, bytes.substr(0, bytes.size() / 2));
  const fs::path png = dir_ / "a.png";
  const uint8_t px[12] = {};
  writePng(png, 2, 2, 3, px);
  const std::string pngBytes = readInputFile(png, "test");
  writeFileAtomic(png, pngBytes.substr(0, pngBytes.size() / 2));
  const fs::path text = dir_ / "text.exr";
  writeFileAtomic(text, "not an image\n");

  for (const fs::path& p : {exr, text}) {
    try {
      readExr(p);
      ADD_FAILURE() << "no exception for " << p;
    } catch (const InputError& e) {
      EXPECT_EQ(e.location().file, p.string());
    }
  }
  for (const fs::path& p : {png, text}) {
    try {
      readPng(p);
      ADD_FAILURE() << "no exception for " << p;
    } catch (const InputError& e) {
      EXPECT_EQ(e.location().file, p.string());
    }
  }
}

}  // namespace
}  // namespace fly
