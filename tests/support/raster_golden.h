// Golden images of the GL engine: a render, tone-mapped linearly at a fixed exposure, against a PNG in
// tests/data/golden (raster output against a threshold, a diff image on failure). Regenerate goldens (after a
// deliberate change, looking at the new images) by running the test with FLY_UPDATE_GOLDEN=1.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "base/image_io.h"
#include "base/tone_map.h"
#include "raster/renderer.h"
#include "rdb/raster_rdb.h"
#include "../raster/raster_test_scenes.h"

namespace fly::raster::test {

inline constexpr uint32_t kGoldenWidth = 160, kGoldenHeight = 90;

// Renders `mode` at 160 × 90 and compares the linear tone-mapped image at `ev100` with the golden
// tests/data/golden/`name`: per channel at most 3 levels off on ≥ 99.5 % of the pixels and no pixel more than
// 48 levels off (rasterisation rules and floating-point order may move an edge pixel between drivers).
// Emission given as a display colour shows at `ev100`'s white, as fly render draws it.
// Scenes with textures, or with frosted glass (its blur reads a mip chain that glGenerateMipmap builds), are
// compared on llvmpipe only, where the goldens were made: how a texture is filtered and how a driver reduces
// mip levels are not specified to the bit (where the sRGB decode happens, the anisotropic footprint, a
// cut-out's edge texels); on an NVIDIA H100 29 % of the textured yard's pixels differ by more than 3 levels,
// and 9 % of the frosted pane's.
inline void checkGolden(RenderMode mode, const rdb::RasterRdb& r, double ev100, const std::string& name) {
  if ((!r.textures.empty() || r.variants.frostedGlass) &&
      context().info().renderer.find("llvmpipe") == std::string::npos) {
    GTEST_SKIP() << "the goldens of textured and frosted scenes are llvmpipe's; this is " << context().info().renderer;
  }
  Renderer renderer;
  renderer.upload(r);
  renderer.setDisplayWhite(1.0f / exposureScale(ev100));
  // The light-map goldens' light maps are synthetic (a few hundred lux under a daylight sky), which the room
  // probe's reflections of that sky would outshine; the probe has tests of its own (room_probe_test.cpp).
  if (mode == RenderMode::kLightMap) renderer.setRoomProbe(false);
  renderer.render(viewOfCamera(r.cameras.at(0)), mode, kGoldenWidth, kGoldenHeight);
  renderer.toneMap({ToneOperator::kLinear, ev100});
  const std::vector<uint8_t> px = renderer.srgb8();
  const int w = int(kGoldenWidth), h = int(kGoldenHeight);
  const std::filesystem::path golden = std::filesystem::path(FLY_TEST_DATA_DIR) / "golden" / name;
  if (std::getenv("FLY_UPDATE_GOLDEN")) {
    writePng(golden, w, h, 3, px.data());
    GTEST_SKIP() << "wrote " << golden;
  }
  ASSERT_TRUE(std::filesystem::exists(golden)) << golden << " is missing: run the test with FLY_UPDATE_GOLDEN=1";
  const ImageU8 g = readPng(golden);
  ASSERT_EQ(g.width, w);
  ASSERT_EQ(g.height, h);
  ASSERT_EQ(g.channels, 3);
  size_t off = 0;
  int worst = 0;
  std::vector<uint8_t> diff(px.size());
  for (size_t i = 0; i < px.size(); ++i) {
    const int d = std::abs(int(px[i]) - int(g.pixels[i]));
    worst = std::max(worst, d);
    off += d > 3;
    diff[i] = uint8_t(std::min(255, d * 8));
  }
  const bool ok = off * 1000 <= px.size() * 5 && worst <= 48;
  if (!ok) {
    const std::filesystem::path out = std::filesystem::absolute("golden-diff-" + name);
    writePng(out, w, h, 3, diff.data());
    writePng(std::filesystem::absolute("golden-actual-" + name), w, h, 3, px.data());
    ADD_FAILURE() << name << ": " << off << " of " << px.size() << " values differ by more than 3, worst "
                  << worst << "; the difference (×8) is in " << out;
  }
}

}  // namespace fly::raster::test
