// Khronos glTF sample models (KhronosGroup/glTF-Sample-Assets, CC BY 4.0; tests/data/khronos/README.md),
// imported and drawn in simple mode, each against a golden that was set after comparing fly's image with the
// model's reference screenshot by eye (docs/validation.md, "Khronos sample models against their screenshots").
//
// The goldens are tests/data/golden/khronos-<model>-simple-160x90.png; regenerate them (after a deliberate
// change, looking at the new images) with FLY_UPDATE_GOLDEN=1 tests/fly_raster_tests --gtest_filter='KhronosGolden.*'.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <optional>
#include <string>

#include "../support/raster_golden.h"
#include "raster/renderer.h"
#include "raster_test_scenes.h"
#include "rdb/raster_rdb.h"
#include "sdb/camera.h"
#include "sdb/gltf_import.h"
#include "sdb/scene.h"

namespace fly::raster {
namespace {

using test::context;

// The model tests/data/khronos/<model>/<model>.gltf seen by a camera at `eyeM` looking at `targetM` with a
// vertical field of `yfovDeg`, in the daylight that fly render gives a plain model without lights (a clear sky
// of turbidity 3 with the sun at 45° elevation), the sun at `sunAzimuthDeg` (clockwise from north, −Z; fly's
// default 135° shines from +X +Z), or in the dark (nullopt).
sdb::Scene khronosModel(const std::string& model, const vec3& eyeM, const vec3& targetM, float yfovDeg,
                        std::optional<double> sunAzimuthDeg = 135.0) {
  sdb::Scene s;
  // This camera first, before the model's own (MultiUVTest has one): the golden is drawn through the first.
  sdb::Camera cam;
  cam.name = "front";
  cam.yfovRad = glm::radians(yfovDeg);
  s.addNode({.name = "eye",
             .parentFromLocal = sdb::lookAtTransform(eyeM, targetM, vec3(0, 1, 0)),
             .camera = s.addCamera(cam).id});
  sdb::importGltf(s, std::filesystem::path(FLY_TEST_DATA_DIR) / "khronos" / model / (model + ".gltf"));
  if (sunAzimuthDeg) {
    s.setTime({.localDateTime = "", .sunDirection = sdb::SunDirection{*sunAzimuthDeg, 45.0}});
    sdb::SkySettings sky;
    sky.model = sdb::SkyModel::kClear;
    sky.turbidity = 3.0;
    sky.sun = true;
    s.setSky(sky);
  }
  return s;
}

void checkKhronos(const sdb::Scene& s, double ev100, const std::string& model) {
  test::checkGolden(RenderMode::kSimple, rdb::buildRasterRdb(s), ev100, "khronos-" + model + "-simple-160x90.png");
}

// OPAQUE ignores the texture's alpha, BLEND fades the stripes from opaque (bottom) to clear (top), MASK cuts
// them at 0.25, 0.5 (the default) and 0.75: a green check beside OPAQUE and BLEND, the green arrows at the
// cut-off heights.
TEST(KhronosGolden, AlphaBlendModeTest) {
  context();
  checkKhronos(khronosModel("AlphaBlendModeTest", vec3(0, 3.0f, 10.5f), vec3(0, 1.05f, 0), 26.0f), 14.5,
               "AlphaBlendModeTest");
}

// doubleSided, and the samplers' CLAMP_TO_EDGE, REPEAT and MIRRORED_REPEAT along s and t: every "Test" box
// like its "Sample pass" box (green checks, two solid green boxes), no red X.
TEST(KhronosGolden, TextureSettingsTest) {
  context();
  checkKhronos(khronosModel("TextureSettingsTest", vec3(0, -0.6f, 22), vec3(0, -0.6f, 0), 27.0f), 14.5,
               "TextureSettingsTest");
}

// Nodes with a negative scale: their triangles' winding flips, so back-face culling keeps the front faces
// (green checks in the scale −1 row, no red X) and the mirrored spheres are lit as the others.
TEST(KhronosGolden, NegativeScaleTest) {
  context();
  checkKhronos(khronosModel("NegativeScaleTest", vec3(0, 0, 22), vec3(0, 0, 0), 24.0f), 14.0,
               "NegativeScaleTest");
}

// The same emissive colour at strengths 1, 2, 4, 8 and 16 (KHR_materials_emissive_strength), in the dark (the
// model's only light is its emitters; its screenshot turns the environment light down) at the exposure whose
// white is 1 cd/m²: there the first cube's display colour (no extension: a fraction of white) and the others'
// luminance (the extension: cd/m²) agree, and each cube is twice as bright as the one to its left.
TEST(KhronosGolden, EmissiveStrengthTest) {
  context();
  const double whiteIsOneCdM2 = std::log2(1.0 / 1.2);  // EV100: white 1.2 · 2^EV100 cd/m²
  checkKhronos(khronosModel("EmissiveStrengthTest", vec3(-2, 6, 24), vec3(0, -1, 0), 26.0f, std::nullopt),
               whiteIsOneCdM2, "EmissiveStrengthTest");
}

// The base colour from TEXCOORD_0 (a colour per face: light blue on −Z, green on −X, white on top) and the
// emission from TEXCOORD_1 (the glTF logo on every face; the first set would show "Multiple UVs not
// supported"), seen from −X −Z as in the screenshot with the sun behind the camera (a rough metal in the shade
// is black in simple mode, which has no environment reflection).
TEST(KhronosGolden, MultiUVTest) {
  context();
  checkKhronos(khronosModel("MultiUVTest", vec3(-5.6f, 4.6f, -6.2f), vec3(0, -0.15f, 0), 30.0f, 315.0), 14.0,
               "MultiUVTest");
}

}  // namespace
}  // namespace fly::raster
