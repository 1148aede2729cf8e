#include "raster/viewer.h"

#include <gtest/gtest.h>

#include <string>

namespace fly::raster {
namespace {

TEST(Viewer, KeyNamesParseCaseInsensitively) {
  EXPECT_EQ(parseViewerAction("3"), ViewerAction::kModeSunlight);
  EXPECT_EQ(parseViewerAction("+"), ViewerAction::kExposureUp);
  EXPECT_EQ(parseViewerAction("-"), ViewerAction::kExposureDown);
  EXPECT_EQ(parseViewerAction("t"), ViewerAction::kTimeForward);
  EXPECT_EQ(parseViewerAction("Shift+T"), ViewerAction::kTimeBack);
  EXPECT_EQ(parseViewerAction("ESC"), ViewerAction::kQuit);
  EXPECT_EQ(parseViewerAction("e"), ViewerAction::kAutoExposure);
  EXPECT_EQ(parseViewerAction("4"), std::nullopt);
  EXPECT_EQ(parseViewerAction(""), std::nullopt);
  EXPECT_EQ(parseViewerAction(" T"), std::nullopt);
}

// Pixel (x, y) of a text image is white (a glyph's pixel), else the dark background.
bool lit(const TextImage& img, uint32_t x, uint32_t y) {
  const uint8_t* p = &img.rgba8[(size_t(y) * img.widthPx + x) * 4];
  EXPECT_EQ(p[3], 255);
  EXPECT_EQ(p[0], p[1]);
  EXPECT_TRUE(p[0] == 255 || p[0] == 32) << int(p[0]);
  return p[0] == 255;
}

TEST(Viewer, TextImageHasTheCellLayoutAndTheGlyphs) {
  // "-": the middle row (glyph row 3) of the first cell, columns 1..5.
  const TextImage minus = rasterizeText("-", 1);
  ASSERT_EQ(minus.widthPx, 7u);
  ASSERT_EQ(minus.heightPx, 9u);
  for (uint32_t y = 0; y < 9; ++y) {
    for (uint32_t x = 0; x < 7; ++x) EXPECT_EQ(lit(minus, x, y), y == 4 && x >= 1 && x <= 5) << x << "," << y;
  }
  // "l" is drawn as "L" in the second cell: its left column and its bottom row, at scale 2.
  const TextImage l = rasterizeText(" l", 2);
  ASSERT_EQ(l.widthPx, 26u);
  ASSERT_EQ(l.heightPx, 18u);
  size_t count = 0;
  for (uint32_t y = 0; y < l.heightPx; ++y) {
    for (uint32_t x = 0; x < l.widthPx; ++x) {
      const uint32_t fx = x / 2, fy = y / 2;  // font pixels
      const bool inGlyph = fx >= 7 && fx <= 11 && fy >= 1 && fy <= 7;
      const bool expected = inGlyph && (fx == 7 || fy == 7);
      EXPECT_EQ(lit(l, x, y), expected) << x << "," << y;
      count += expected ? 1 : 0;
    }
  }
  EXPECT_EQ(count, 4u * (7 + 4));  // 11 font pixels of 2×2
  // Characters outside the font show as '?', the same as '?' itself.
  EXPECT_EQ(rasterizeText("~", 1).rgba8, rasterizeText("?", 1).rgba8);
  EXPECT_NE(rasterizeText("0", 1).rgba8, rasterizeText("O", 1).rgba8);
}

TEST(Viewer, EveryPrintableCharacterHasADistinctGlyph) {
  for (int a = 0x21; a <= 0x5F; ++a) {
    const TextImage ia = rasterizeText(std::string(1, char(a)), 1);
    size_t on = 0;
    for (uint32_t i = 0; i < ia.widthPx * ia.heightPx; ++i) on += ia.rgba8[4 * i] == 255 ? 1 : 0;
    EXPECT_GT(on, 0u) << char(a);
    for (int b = a + 1; b <= 0x5F; ++b) {
      EXPECT_NE(ia.rgba8, rasterizeText(std::string(1, char(b)), 1).rgba8) << char(a) << " " << char(b);
    }
  }
}

}  // namespace
}  // namespace fly::raster
