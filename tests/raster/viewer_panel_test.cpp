// The viewer's panel headless: ImGui's own headless setup (a display size, no platform backend) for layout
// and input, and its OpenGL3 backend drawing into the EGL context the GL tests use.
#include "raster/viewer_panel.h"

#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <algorithm>

#include "tests/raster/panel_input.h"
#include "tests/raster/raster_test_scenes.h"

namespace fly::raster {
namespace {

using test::kPanelDisplayH;
using test::kPanelDisplayW;
using test::panelFrame;

PanelState sampleState() {
  PanelState s;
  s.modes = {RenderMode::kLightMap, RenderMode::kSunlight, RenderMode::kSimple};
  s.mode = RenderMode::kSunlight;
  s.tone = ToneMapSettings{ToneOperator::kFilmic, 12.0, 4.0f};
  s.autoExposure = false;
  s.cameraNames = {"entrance", "desk"};
  s.camera = 0;
  s.clock = LocalClock{2026, 9, 15, 17 * 60 + 30};
  s.timeLabel = "2026-09-15 17:30 +03:00";
  s.probeAvailable = true;
  s.probeText = "245 lux";
  return s;
}

TEST(ViewerPanel, DayOfYearRoundTrips) {
  EXPECT_EQ(dayOfYear(LocalClock{2026, 1, 1, 0}), 1);
  EXPECT_EQ(dayOfYear(LocalClock{2026, 9, 15, 0}), 258);   // 243 days in January–August
  EXPECT_EQ(dayOfYear(LocalClock{2028, 12, 31, 0}), 366);  // a leap year
  const LocalClock c = withDayOfYear(LocalClock{2026, 9, 15, 600}, 172);
  EXPECT_EQ(c, (LocalClock{2026, 6, 21, 600}));
  EXPECT_EQ(withDayOfYear(LocalClock{2026, 1, 1, 0}, 400), (LocalClock{2026, 12, 31, 0}));  // clamped
}

TEST(ViewerPanel, ClickingTheTimeSliderSetsThatTime) {
  ViewerPanel panel;
  const PanelState state = sampleState();
  for (const float f : {0.1f, 0.5f, 0.9f}) {
    int expected = -1;
    const PanelEdits edits = test::clickTimeSlider(panel, state, f, expected);
    ASSERT_TRUE(edits.clock) << f;
    EXPECT_NEAR(edits.clock->minuteOfDay, expected, 1) << f;
    EXPECT_NEAR(edits.clock->minuteOfDay, f * 1439.0f, 0.1f * 1439.0f) << f;
    EXPECT_EQ(edits.clock->day, 15);  // the date stays
    EXPECT_EQ(edits.clock->month, 9);
    EXPECT_FALSE(edits.mode || edits.ev100 || edits.op || edits.camera || edits.autoExposure);
  }
}

TEST(ViewerPanel, KeysAndClicksOutsideThePanelStayTheViewers) {
  ViewerPanel panel;
  const PanelState state = sampleState();
  test::layOut(panel, state);
  const PanelLayout l = panel.layout();
  ASSERT_GT(l.windowMax[0], l.windowMin[0]);
  ASSERT_LT(l.windowMax[0], kPanelDisplayW - 10.0f) << "the panel covers the whole display";
  // The mouse over the panel: ImGui wants it; over the scene (bottom right corner): it does not.
  panelFrame(panel, state, 0.5f * (l.windowMin[0] + l.windowMax[0]), l.windowMin[1] + 5.0f, false);
  EXPECT_TRUE(panel.wantsMouse());
  panelFrame(panel, state, kPanelDisplayW - 5.0f, kPanelDisplayH - 5.0f, false);
  EXPECT_FALSE(panel.wantsMouse());
  EXPECT_FALSE(panel.wantsKeyboard());  // no widget is being typed into
  // A press over the scene changes nothing in the panel.
  EXPECT_FALSE(panelFrame(panel, state, kPanelDisplayW - 5.0f, kPanelDisplayH - 5.0f, true).any());
  panelFrame(panel, state, kPanelDisplayW - 5.0f, kPanelDisplayH - 5.0f, false);
  // Hidden, the panel takes nothing, even a click where its slider was.
  panel.setVisible(false);
  int expected = 0;
  EXPECT_FALSE(test::clickTimeSlider(panel, state, 0.5f, expected).any());
  EXPECT_FALSE(panel.wantsMouse());
  EXPECT_FALSE(panel.wantsKeyboard());
}

TEST(ViewerPanel, WithoutATimeOfDayThereAreNoSliders) {
  ViewerPanel panel;
  PanelState state = sampleState();
  state.clock.reset();
  test::layOut(panel, state);
  EXPECT_EQ(panel.layout().timeSliderMax[0], 0.0f);
}

// The tone-mapped image of a lit quad, the panel drawn over it by the OpenGL3 backend in the headless EGL
// context: hidden, the image is unchanged bit for bit; shown, it differs inside the panel's window only.
TEST(ViewerPanel, DrawsHeadlessAndHiddenLeavesTheImageAlone) {
  test::context();
  sdb::Scene scene;
  sdb::Material m;
  m.diffuseColor = Rgb(0.5f, 0.6f, 0.7f);
  const sdb::MaterialId material = scene.addMaterial(m).id;
  const sdb::MeshId mesh = scene.addMesh(test::quadXY(material)).id;
  const sdb::NodeId node = scene.addNode({.name = "quad", .meshes = {mesh}}).id;
  rdb::LightMapStore store;  // a different irradiance (lux) at each corner: a gradient to tone-map
  store.meshes.push_back(
      {node.value, mesh.value, {{100, 200, 300}, {400, 250, 50}, {1000, 800, 600}, {30, 60, 90}}, {}});
  const rdb::RasterRdb rdb = rdb::buildRasterRdb(scene, &store);
  Renderer renderer;
  renderer.upload(rdb);
  const uint32_t w = uint32_t(kPanelDisplayW), h = uint32_t(kPanelDisplayH);
  renderer.render(test::lookAtView(vec3(0, 0, 2.5f), vec3(0), 100.0f), RenderMode::kLightMap, w, h);
  renderer.toneMap(ToneMapSettings{ToneOperator::kFilmic, 2.0, 4.0f});
  const std::vector<uint8_t> image = renderer.srgb8();  // RGB8, rows from the top
  ASSERT_EQ(image.size(), size_t(w) * h * 3);

  // A window stand-in: an RGBA8 framebuffer holding the image (GL's rows from the bottom).
  GLuint tex = 0, fbo = 0;
  glCreateTextures(GL_TEXTURE_2D, 1, &tex);
  glTextureStorage2D(tex, 1, GL_RGBA8, GLsizei(w), GLsizei(h));
  glCreateFramebuffers(1, &fbo);
  glNamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT0, tex, 0);
  auto drawOverImage = [&](ViewerPanel& panel) {
    std::vector<uint8_t> rows(size_t(w) * h * 3);
    for (uint32_t y = 0; y < h; ++y)
      std::copy_n(&image[size_t(h - 1 - y) * w * 3], w * 3, &rows[size_t(y) * w * 3]);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage2D(tex, 0, 0, 0, GLsizei(w), GLsizei(h), GL_RGB, GL_UNSIGNED_BYTE, rows.data());
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    test::layOut(panel, sampleState());
    panel.render();
    std::vector<uint8_t> back(size_t(w) * h * 3), out(back.size());
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, GLsizei(w), GLsizei(h), GL_RGB, GL_UNSIGNED_BYTE, back.data());
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    for (uint32_t y = 0; y < h; ++y)
      std::copy_n(&back[size_t(h - 1 - y) * w * 3], w * 3, &out[size_t(y) * w * 3]);
    return out;
  };

  ViewerPanel panel;
  panel.initGl();
  panel.setVisible(false);
  EXPECT_TRUE(drawOverImage(panel) == image) << "the hidden panel changed the image";

  panel.setVisible(true);
  const std::vector<uint8_t> shown = drawOverImage(panel);
  const PanelLayout& l = panel.layout();
  size_t changedInside = 0, changedOutside = 0, inside = 0;
  for (uint32_t y = 0; y < h; ++y) {
    for (uint32_t x = 0; x < w; ++x) {
      const float fx = float(x), fy = float(y);  // one pixel of slack for the window's edges
      const bool in = fx + 1.0f >= l.windowMin[0] && fx <= l.windowMax[0] + 1.0f &&
                      fy + 1.0f >= l.windowMin[1] && fy <= l.windowMax[1] + 1.0f;
      const size_t i = (size_t(y) * w + x) * 3;
      const bool changed = !std::equal(&shown[i], &shown[i] + 3, &image[i]);
      inside += in;
      (in ? changedInside : changedOutside) += changed;
    }
  }
  EXPECT_EQ(changedOutside, 0u);
  EXPECT_GT(changedInside, inside / 2) << "the panel's window is not drawn";
  glDeleteFramebuffers(1, &fbo);
  glDeleteTextures(1, &tex);
}

}  // namespace
}  // namespace fly::raster
