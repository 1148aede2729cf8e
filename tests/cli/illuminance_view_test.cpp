// The false-colour view of a bake's illuminance: lux from the rendered luminance of white, marker-emitting
// surfaces, and the image read back through its legend; the scene prepared for it.
#include "cli/illuminance_view.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "base/file_io.h"
#include "base/image_io.h"
#include "base/math.h"

namespace fly::cli {
namespace {

namespace fs = std::filesystem;

TEST(IlluminanceView, LuxIsPiTimesLuminanceAboveTheMarker) {
  // E = 100 lx on white: L = 100/π + marker (grey); E = 3000 lx of warm light; nothing seen: 0.
  const float grey = float(100.0 / kPi) + kIlluminanceMarkerCdM2;
  const Rgb warm = Rgb(1.2f, 1.0f, 0.6f) * float(3000.0 / kPi / double(luminance(Rgb(1.2f, 1.0f, 0.6f))));
  const std::vector<float> rgb = {grey,   grey,   grey,   warm.r + kIlluminanceMarkerCdM2,
                                  warm.g + kIlluminanceMarkerCdM2, warm.b + kIlluminanceMarkerCdM2,
                                  0.0f,   0.0f,   0.0f,   kIlluminanceMarkerCdM2,
                                  kIlluminanceMarkerCdM2, kIlluminanceMarkerCdM2};
  const std::vector<double> lux = illuminanceFromRender(rgb);
  ASSERT_EQ(lux.size(), 4u);
  EXPECT_NEAR(lux[0], 100.0, 1e-3);
  EXPECT_NEAR(lux[1], 3000.0, 0.05);
  EXPECT_TRUE(std::isnan(lux[2]));  // background
  EXPECT_NEAR(lux[3], 0.0, 1e-6);   // a surface in the dark: 0 lx, seen
}

TEST(IlluminanceView, PixelsReadBackThroughTheLegend) {
  const fs::path png = fs::temp_directory_path() / "fly_illuminance_view_test.png";
  IlluminanceView v;
  v.widthPx = 320;
  v.heightPx = 200;
  // Lux rising from 20 to 20 000 along x (log), background in the top rows.
  for (int y = 0; y < v.heightPx; ++y) {
    for (int x = 0; x < v.widthPx; ++x) {
      v.lux.push_back(y < 20 ? NAN : 20.0 * std::pow(1000.0, x / double(v.widthPx - 1)));
    }
  }
  v.scale = falseColourScale(v.lux, true);
  ASSERT_DOUBLE_EQ(v.scale.minValue, 20.0);
  ASSERT_DOUBLE_EQ(v.scale.maxValue, 20000.0);
  v.metadata.text = {{"fly:quantity", "illuminance"}};
  drawIlluminanceView(v, png);
  const ImageU8 image = readPng(png);
  const LegendBox box = illuminanceLegendBox(v.widthPx, v.heightPx);
  ASSERT_GT(image.width, int(box.leftPx + box.widthPx));
  auto at = [&](int x, int y) {
    const uint8_t* p = &image.pixels[(size_t(y) * size_t(image.width) + size_t(x)) * size_t(image.channels)];
    return Rgb8{p[0], p[1], p[2]};
  };
  auto distance = [](const Rgb8& a, const Rgb8& b) {
    return std::abs(a.r - b.r) + std::abs(a.g - b.g) + std::abs(a.b - b.b);
  };
  EXPECT_EQ(distance(at(10, 5), Rgb8{255, 255, 255}), 0) << "background is white";
  const int middle = int(box.leftPx + 0.5 * box.widthPx);
  for (int x = 0; x < v.widthPx; x += 29) {
    const Rgb8 seen = at(x, 100);
    int best = int(box.topPx);
    for (int y = int(box.topPx); y < int(box.bottomPx); ++y) {
      if (distance(at(middle, y), seen) < distance(at(middle, best), seen)) best = y;
    }
    const double t = (box.bottomPx - (best + 0.5)) / (box.bottomPx - box.topPx);
    const double expected = v.lux[size_t(100) * size_t(v.widthPx) + size_t(x)];
    EXPECT_NEAR(v.scale.valueAt(t), expected, 0.05 * expected) << "x " << x;
  }
  fs::remove(png);
}

TEST(IlluminanceView, SceneBecomesWhiteWithClearPanesAndNoDaylight) {
  sdb::Scene scene;
  sdb::Material red;
  red.diffuseColor = Rgb(0.7f, 0.1f, 0.1f);
  sdb::Material glass;
  glass.diffuseColor = Rgb(0.0f);
  glass.transmissionColor = Rgb(0.9f);
  glass.reflectionColor = Rgb(1.0f);
  const sdb::MaterialId redId = scene.addMaterial(red).id;
  const sdb::MaterialId glassId = scene.addMaterial(glass).id;
  sdb::Mesh wall, pane, plain;
  wall.material = redId;
  pane.material = glassId;
  const sdb::MeshId wallId = scene.addMesh(wall).id, paneId = scene.addMesh(pane).id,
                    plainId = scene.addMesh(plain).id;  // the default material
  sdb::SkySettings sky;
  sky.model = sdb::SkyModel::kClear;
  sky.sun = true;
  scene.setSky(sky);
  showIlluminance(scene);
  for (const sdb::MeshId id : {wallId, plainId}) {
    const sdb::Material& m = scene.material(scene.mesh(id).material);
    EXPECT_EQ(m.effective().diffuse, Rgb(1.0f));
    EXPECT_EQ(m.emissionLuminance, Rgb(kIlluminanceMarkerCdM2));
  }
  const sdb::Material& p = scene.material(scene.mesh(paneId).material);
  EXPECT_TRUE(p.hasClearTransmission());
  EXPECT_EQ(p.effective().transmission, Rgb(1.0f));
  EXPECT_EQ(scene.sky().model, sdb::SkyModel::kNone);
  EXPECT_FALSE(scene.sky().sun);
}

}  // namespace
}  // namespace fly::cli
