// `fly view`'s scene host under the panel: a click on the panel's time slider sets the scene's time, and the
// sun the RasterRdb hands the renderer is sunsky's sun for that local time; times the clock skips are refused
// without changing anything.
#include "cli/view_host.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "base/math.h"
#include "sunsky/civil_time.h"
#include "sunsky/sun_position.h"
#include "tests/raster/panel_input.h"

namespace fly::cli {
namespace {

namespace fs = std::filesystem;

// box-room: latitude 60.17° N, longitude 24.94° E, 10 m, Europe/Helsinki, north along −Z (north angle 0),
// clear sky with the sun, 2026-09-15T17:30.
const fs::path kBoxRoom = fs::path(FLY_SOURCE_DIR) / "scenes/box-room/box-room.json";

// The world direction towards the sun at a local time in box-room, from sunsky's solar position (NREL SPA)
// alone: east +X, north −Z, up +Y.
vec3 expectedSunDirWorld(const raster::LocalClock& c) {
  char text[32];
  std::snprintf(text, sizeof text, "%04d-%02d-%02dT%02d:%02d", c.year, c.month, c.day, c.minuteOfDay / 60,
                c.minuteOfDay % 60);
  sunsky::SpaInput spa;
  spa.utc = sunsky::parseTime(text, "Europe/Helsinki");
  spa.latitudeDeg = 60.17;
  spa.longitudeDeg = 24.94;
  spa.elevationM = 10.0;
  const sunsky::SunPosition sun = sunsky::sunPosition(spa);
  const double az = sun.azimuthDeg * kPi / 180.0, el = sun.apparentElevationDeg() * kPi / 180.0;
  return vec3(float(std::sin(az) * std::cos(el)), float(std::sin(el)), float(-std::cos(az) * std::cos(el)));
}

TEST(ViewHost, ThePanelsTimeSliderMovesTheSunTheRendererDraws) {
  RasterScene scene = loadRasterScene(kBoxRoom, DaylightOptions{});
  rdb::RasterRdb rdb = rdb::buildRasterRdb(scene.scene);
  SceneViewHost host(scene, rdb);
  const std::optional<raster::LocalClock> start = host.localClock();
  ASSERT_TRUE(start);
  EXPECT_EQ(*start, (raster::LocalClock{2026, 9, 15, 17 * 60 + 30}));
  ASSERT_TRUE(rdb.sky);
  EXPECT_LT(glm::length(rdb.sky->sunDirWorld - expectedSunDirWorld(*start)), 1e-4f);

  raster::ViewerPanel panel;
  raster::PanelState state;
  state.modes = {raster::RenderMode::kSunlight};
  state.mode = raster::RenderMode::kSunlight;
  state.clock = start;
  int expectedMinute = -1;
  const raster::PanelEdits edits = raster::test::clickTimeSlider(panel, state, 0.42f, expectedMinute);
  ASSERT_TRUE(edits.clock);
  EXPECT_NEAR(edits.clock->minuteOfDay, expectedMinute, 1);
  EXPECT_GT(edits.clock->minuteOfDay, 8 * 60);  // a morning sun, well away from 17:30's
  EXPECT_LT(edits.clock->minuteOfDay, 12 * 60);

  std::string message;
  const std::optional<rdb::RasterRdbChanges> changes = host.setLocalClock(*edits.clock, message);
  EXPECT_EQ(message, "");
  ASSERT_TRUE(changes);
  EXPECT_TRUE(changes->sky);  // the renderer re-uploads the sky and sun (Renderer::update)
  EXPECT_FALSE(changes->geometry);
  EXPECT_EQ(host.localClock(), edits.clock);
  const vec3 expected = expectedSunDirWorld(*edits.clock);
  EXPECT_LT(glm::length(rdb.sky->sunDirWorld - expected), 1e-4f)
      << rdb.sky->sunDirWorld.x << " " << rdb.sky->sunDirWorld.y << " " << rdb.sky->sunDirWorld.z;
  EXPECT_GT(glm::length(expected - expectedSunDirWorld(*start)), 0.3f);  // the sun moved
  // The same as building the scene at that time.
  EXPECT_EQ(rdb, rdb::buildRasterRdb(scene.scene));

  // The date slider's day: the summer solstice at the same time of day.
  raster::LocalClock solstice = *edits.clock;
  solstice.month = 6;
  solstice.day = 21;
  ASSERT_TRUE(host.setLocalClock(solstice, message));
  EXPECT_EQ(message, "");
  EXPECT_LT(glm::length(rdb.sky->sunDirWorld - expectedSunDirWorld(solstice)), 1e-4f);
}

TEST(ViewHost, ATimeTheClockSkipsIsRefusedAndTheTimeStays) {
  RasterScene scene = loadRasterScene(kBoxRoom, DaylightOptions{});
  rdb::RasterRdb rdb = rdb::buildRasterRdb(scene.scene);
  SceneViewHost host(scene, rdb);
  const rdb::RasterRdb before = rdb;
  // Helsinki's clocks go from 03:00 to 04:00 on 29 March 2026 (EU summer time, last Sunday of March).
  std::string message;
  host.setLocalClock(raster::LocalClock{2026, 3, 29, 3 * 60 + 30}, message);
  EXPECT_NE(message, "");
  EXPECT_EQ(host.localClock(), (raster::LocalClock{2026, 9, 15, 17 * 60 + 30}));
  EXPECT_EQ(rdb, before);
}

TEST(ViewHost, ASceneWithoutASiteHasNoClock) {
  RasterScene scene =
      loadRasterScene(fs::path(FLY_SOURCE_DIR) / "scenes/cornell-box/cornell-box.json", DaylightOptions{});
  rdb::RasterRdb rdb = rdb::buildRasterRdb(scene.scene);
  SceneViewHost host(scene, rdb);
  EXPECT_FALSE(host.localClock());
  std::string message;
  EXPECT_FALSE(host.setLocalClock(raster::LocalClock{}, message));
  EXPECT_EQ(message, "no time of day: the scene has no site");
}

}  // namespace
}  // namespace fly::cli
