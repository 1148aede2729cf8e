// The daylight options and the default daylight of a plain glTF model (cli/scene_daylight.h): the default's
// figures against sunsky's for the same sun, each option overriding a scene file's value, contradictory and
// invalid options as usage errors naming the option, the bake's record, and the lowering to the GL engine.
#include "cli/scene_daylight.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "base/error.h"
#include "rdb/raster_rdb.h"
#include "rdb/site_lowering.h"
#include "sdb/scene_load.h"
#include "sunsky/civil_time.h"
#include "sunsky/clear_sky.h"
#include "sunsky/hosek_wilkie.h"
#include "sunsky/sun_disc.h"
#include "sunsky/sun_position.h"

namespace fly::cli {
namespace {

namespace fs = std::filesystem;

// A glTF model without lights or emissive materials, and a scene file with a site, time and clear sky.
const fs::path kPlainModel = fs::path(FLY_SOURCE_DIR) / "scenes/open-surfaces/open-surfaces.gltf";
const fs::path kHouse = fs::path(FLY_SOURCE_DIR) / "scenes/house/house.json";

TEST(DefaultDaylight, PlainModelWithoutLightsGetsTheStatedClearSkyAndSun) {
  const LitScene lit = loadLitScene(kPlainModel, {});
  EXPECT_TRUE(lit.defaultDaylight);
  const sdb::Scene& s = lit.scene;
  EXPECT_EQ(s.sky().model, sdb::SkyModel::kClear);
  EXPECT_TRUE(s.sky().sun);
  EXPECT_EQ(s.sky().turbidity, 3.0);
  ASSERT_TRUE(s.time().sunDirection);
  EXPECT_EQ(s.time().sunDirection->azimuthDeg, 135.0);
  EXPECT_EQ(s.time().sunDirection->elevationDeg, 45.0);
  EXPECT_FALSE(s.hasSite());

  const std::optional<rdb::SceneDaylight> d = rdb::lowerDaylight(s);
  ASSERT_TRUE(d && d->sun && d->sky);
  // Azimuth 135° clockwise from north (−Z) at 45°: towards +X (east) and +Z (south) equally, and up.
  EXPECT_NEAR(d->sunDirWorld.x, 0.5, 1e-9);
  EXPECT_NEAR(d->sunDirWorld.y, std::sqrt(0.5), 1e-9);
  EXPECT_NEAR(d->sunDirWorld.z, 0.5, 1e-9);
  // The sun's horizontal illuminance is the Hosek–Wilkie sun at zenith 45°, turbidity 3, at the mean
  // Earth–Sun distance (day 93: eccentricity correction 1.000).
  sunsky::SunDiscInput in;
  in.zenithDeg = 45.0;
  in.azimuthDeg = 135.0;
  in.turbidity = 3.0;
  in.pressureHpa = 1013.25;
  in.dayOfYear = 93;
  EXPECT_NEAR(sunsky::eccentricityCorrection(93), 1.0, 5e-4);
  const double expectedDirectHorizontalLux =
      double(luminance(sunsky::hosekWilkieSunDisc(in).normalIlluminanceLux)) * std::cos(degToRad(45.0));
  const double directHorizontalLux = double(luminance(d->sun->normalIlluminanceLux)) * d->sun->dirEnu.z;
  EXPECT_NEAR(directHorizontalLux, expectedDirectHorizontalLux, 1e-6 * expectedDirectHorizontalLux);
  // The model's authors' reference implementation: 76 550 lx direct normal, 16 780 lx diffuse horizontal
  // (ground albedo 0.2; sunsky/hosek_wilkie_test.cpp).
  EXPECT_NEAR(directHorizontalLux, 76550.2 * std::cos(degToRad(45.0)), 0.01 * 54000.0);
  EXPECT_NEAR(sunsky::horizontalIlluminanceLux(*d->sky), 16779.7, 0.003 * 16779.7);
  // The line the commands print names the default and how to change it.
  EXPECT_NE(lit.light.find("default daylight (no lights in open-surfaces.gltf): clear sky (Hosek-Wilkie), turbidity 3.0, sun "
                           "placed at 45.0° elevation, azimuth 135.0° (south-east)"),
            std::string::npos)
      << lit.light;
  EXPECT_NE(lit.light.find("give --lat --lon --time"), std::string::npos);
}

TEST(DefaultDaylight, SimpleModeShadesWithTheSunAndTheSkyAmbient) {
  const LitScene lit = loadLitScene(kPlainModel, {});
  const rdb::RasterRdb r = rdb::buildRasterRdb(lit.scene);
  EXPECT_TRUE(r.variants.sun);
  EXPECT_TRUE(r.variants.sky);
  EXPECT_TRUE(r.lights.empty());
  // No lights: the simple mode's ambient is the daylight's, the sky's horizontal illuminance above.
  EXPECT_EQ(r.ambient, r.daylightAmbient);
  EXPECT_GT(luminance(r.ambient.upLux), 10000.0f);
  EXPECT_GT(luminance(r.ambient.downLux), 0.0f);
}

TEST(DefaultDaylight, NotForAModelWithLightsOrAScene) {
  sdb::Scene withLight = sdb::loadScene(kPlainModel);
  withLight.addNode({.name = "lamp", .light = withLight.addLight(sdb::Light{}).id});
  EXPECT_FALSE(applyDaylightOptions(withLight, {}, true));
  EXPECT_EQ(withLight.sky().model, sdb::SkyModel::kNone);
  EXPECT_FALSE(withLight.sky().sun);
  EXPECT_EQ(describeLight(withLight, false), "1 light");
  // A material that emits light in cd/m², however dimly, lights the model (no default daylight); emission
  // as a display colour (glTF's without KHR_materials_emissive_strength) lights nothing, and the model gets
  // the default daylight.
  for (const float cdM2 : {0.0f, 0.5f, 10.0f, 1e5f}) {
    for (const bool display : {false, true}) {
      sdb::Scene s = sdb::loadScene(kPlainModel);
      const sdb::MaterialId id = s.mesh(s.meshes().begin()->first).material;
      ASSERT_NE(id.value, 0u);
      sdb::Material m = s.material(id);
      m.emissionLuminance = Rgb(cdM2);
      m.emissionDisplay = display;
      s.setMaterial(id, m);
      EXPECT_EQ(applyDaylightOptions(s, {}, true), cdM2 == 0.0f || display)
          << cdM2 << (display ? " display colour" : " cd/m²");
    }
  }
  // The same model placed by a scene file is lit as the file says (here: no default when it has daylight).
  const LitScene house = loadLitScene(kHouse, {});
  EXPECT_FALSE(house.defaultDaylight);
  EXPECT_EQ(house.scene.time().localDateTime, "2026-06-21T15:00");
}

TEST(DaylightOptions, SiteAndTimeOnAPlainModelGiveTheSunOfSunsky) {
  DaylightOptions o;
  o.latitudeDeg = 60.17;
  o.longitudeDeg = 24.94;
  o.timeZone = "Europe/Helsinki";
  o.time = "2026-06-21T15:00";
  const LitScene lit = loadLitScene(kPlainModel, o);
  EXPECT_FALSE(lit.defaultDaylight);
  EXPECT_EQ(lit.scene.sky().model, sdb::SkyModel::kClear);
  EXPECT_TRUE(lit.scene.sky().sun);
  sunsky::SpaInput spa;
  spa.latitudeDeg = 60.17;
  spa.longitudeDeg = 24.94;
  spa.utc = sunsky::parseTime("2026-06-21T12:00:00Z", "");
  const sunsky::SunPosition expected = sunsky::sunPosition(spa);
  const std::optional<rdb::SceneDaylight> d = rdb::lowerDaylight(lit.scene);
  ASSERT_TRUE(d);
  EXPECT_NEAR(d->sunPosition.apparentZenithDeg, expected.apparentZenithDeg, 1e-9);
  EXPECT_NEAR(d->sunPosition.azimuthDeg, expected.azimuthDeg, 1e-9);
  EXPECT_NE(lit.light.find("site 60.1700° N, 24.9400° E, 2026-06-21T15:00 Europe/Helsinki"), std::string::npos)
      << lit.light;
  // A time that carries its zone needs no --tz.
  o.timeZone.clear();
  o.time = "2026-06-21T12:00:00Z";
  const std::optional<rdb::SceneDaylight> utc = rdb::lowerDaylight(loadLitScene(kPlainModel, o).scene);
  ASSERT_TRUE(utc);
  EXPECT_NEAR(utc->sunPosition.azimuthDeg, expected.azimuthDeg, 1e-9);
}

TEST(DaylightOptions, AnOvercastSkyWithThePlacedSunHasTheIesHandbooksLevel) {
  DaylightOptions o;
  o.sky = "cie:1";
  o.sunDirection = "180,30";
  const LitScene lit = loadLitScene(kPlainModel, o);
  EXPECT_FALSE(lit.scene.sky().sun);
  const std::optional<rdb::SceneDaylight> d = rdb::lowerDaylight(lit.scene);
  ASSERT_TRUE(d && d->sky);
  EXPECT_FALSE(d->sun);
  // IES Lighting Handbook, overcast sky: 0.3 + 21·sin α klx, α = 30°.
  EXPECT_NEAR(sunsky::horizontalIlluminanceLux(*d->sky), 10800.0, 0.01 * 10800.0);
}

TEST(DaylightOptions, EachOverridesTheSceneFilesValue) {
  const sdb::Scene base = sdb::loadScene(kHouse);
  const auto with = [](auto set) {
    DaylightOptions o;
    set(o);
    return loadLitScene(kHouse, o).scene;
  };
  EXPECT_EQ(with([](DaylightOptions& o) { o.latitudeDeg = 10.0; }).site().latitudeDeg, 10.0);
  EXPECT_EQ(with([](DaylightOptions& o) { o.longitudeDeg = -70.5; }).site().longitudeDeg, -70.5);
  EXPECT_EQ(with([](DaylightOptions& o) { o.elevationM = 1200.0; }).site().elevationM, 1200.0);
  EXPECT_EQ(with([](DaylightOptions& o) { o.northAngleDeg = 30.0; }).site().northAngleDeg, 30.0);
  EXPECT_EQ(with([](DaylightOptions& o) { o.timeZone = "+02:00"; }).site().timeZone, "+02:00");
  EXPECT_EQ(with([](DaylightOptions& o) { o.time = "2026-12-21T10:00"; }).time().localDateTime, "2026-12-21T10:00");
  EXPECT_EQ(with([](DaylightOptions& o) { o.turbidity = 6.0; }).sky().turbidity, 6.0);
  const sdb::Scene overcast = with([](DaylightOptions& o) { o.sky = "cie:3"; });
  EXPECT_EQ(overcast.sky().model, sdb::SkyModel::kCie);
  EXPECT_EQ(overcast.sky().cieType, 3);
  EXPECT_FALSE(overcast.sky().sun);
  const sdb::Scene placed = with([](DaylightOptions& o) { o.sunDirection = "200,30.5"; });
  ASSERT_TRUE(placed.time().sunDirection);
  EXPECT_EQ(placed.time().sunDirection->azimuthDeg, 200.0);
  EXPECT_EQ(placed.time().sunDirection->elevationDeg, 30.5);
  EXPECT_TRUE(placed.time().localDateTime.empty());
  // An option leaves the other values as the scene file has them.
  const sdb::Scene lat = with([](DaylightOptions& o) { o.latitudeDeg = 10.0; });
  EXPECT_EQ(lat.site().longitudeDeg, base.site().longitudeDeg);
  EXPECT_EQ(lat.site().timeZone, base.site().timeZone);
  EXPECT_EQ(lat.time().localDateTime, base.time().localDateTime);
  EXPECT_EQ(lat.sky().model, base.sky().model);
}

// The usage error of `o` applied to `scene`, or "" when there is none.
std::string usageError(const fs::path& scene, const DaylightOptions& o) {
  try {
    loadLitScene(scene, o);
  } catch (const UsageError& e) {
    return e.what();
  }
  return "";
}

TEST(DaylightOptions, ContradictoryOrInvalidOptionsAreUsageErrorsNamingTheOption) {
  struct Case {
    const char* name;
    fs::path scene;
    DaylightOptions o;
    const char* text;
  };
  DaylightOptions sunAndSite;
  sunAndSite.sunDirection = "135,45";
  sunAndSite.latitudeDeg = 60.0;
  sunAndSite.longitudeDeg = 25.0;
  DaylightOptions sunAndTime;
  sunAndTime.sunDirection = "135,45";
  sunAndTime.time = "2026-06-21T12:00";
  DaylightOptions latOnly;
  latOnly.latitudeDeg = 60.0;
  DaylightOptions timeOnly;
  timeOnly.time = "2026-06-21T12:00Z";
  DaylightOptions localWithoutZone;
  localWithoutZone.latitudeDeg = 60.0;
  localWithoutZone.longitudeDeg = 25.0;
  localWithoutZone.time = "2026-06-21T12:00";
  DaylightOptions siteWithoutTime;
  siteWithoutTime.latitudeDeg = 60.0;
  siteWithoutTime.longitudeDeg = 25.0;
  DaylightOptions northWithoutSite;
  northWithoutSite.northAngleDeg = 90.0;
  DaylightOptions weatherWithoutPerez;
  weatherWithoutPerez.weatherFile = (fs::path(FLY_TEST_DATA_DIR) / "epw/helsinki-jun21-22.epw").string();
  DaylightOptions perezWithoutWeather;
  perezWithoutWeather.sky = "perez";
  DaylightOptions perezWithSunDir = weatherWithoutPerez;
  perezWithSunDir.sky = "perez";
  perezWithSunDir.sunDirection = "180,40";
  DaylightOptions turbid;
  turbid.turbidity = 20.0;
  DaylightOptions latitude91;
  latitude91.latitudeDeg = 91.0;
  latitude91.longitudeDeg = 0.0;
  DaylightOptions azimuth360;
  azimuth360.sunDirection = "360,10";
  DaylightOptions sunDirOneValue;
  sunDirOneValue.sunDirection = "45";
  DaylightOptions foggy;
  foggy.sky = "foggy";
  DaylightOptions cie16;
  cie16.sky = "cie:16";
  DaylightOptions month13;
  month13.time = "2026-13-01T12:00";
  DaylightOptions mars;
  mars.timeZone = "Mars/Olympus";
  const Case cases[] = {
      {"sun direction with a site", kPlainModel, sunAndSite, "--sun-dir places the sun directly and --lat"},
      {"sun direction with a time", kHouse, sunAndTime, "--sun-dir places the sun directly and --time"},
      {"latitude alone", kPlainModel, latOnly, "--lat places the model on Earth together with --lon"},
      {"time without a site", kPlainModel, timeOnly, "--time needs a site"},
      {"local time without a zone", kPlainModel, localWithoutZone, "give --tz"},
      {"site without a time", kPlainModel, siteWithoutTime, "give --time"},
      {"north without a site", kPlainModel, northWithoutSite, "--north needs a site"},
      {"weather without the Perez sky", kHouse, weatherWithoutPerez, "--weather"},
      {"Perez sky without weather", kHouse, perezWithoutWeather, "give --weather FILE.epw"},
      {"Perez sky with a sun direction", kHouse, perezWithSunDir, "--sun-dir: a Perez sky"},
      {"turbidity 20", kPlainModel, turbid, "--turbidity 20"},
      {"latitude 91", kPlainModel, latitude91, "--lat 91"},
      {"azimuth 360", kPlainModel, azimuth360, "--sun-dir 360,10"},
      {"sun direction of one value", kPlainModel, sunDirOneValue, "--sun-dir 45: expected AZIMUTH,ELEVATION"},
      {"unknown sky", kPlainModel, foggy, "--sky foggy"},
      {"CIE type 16", kPlainModel, cie16, "--sky cie:16"},
      {"month 13", kHouse, month13, "--time"},
      {"unknown zone", kHouse, mars, "Mars/Olympus"},
  };
  for (const Case& c : cases) {
    const std::string message = usageError(c.scene, c.o);
    EXPECT_NE(message.find(c.text), std::string::npos) << c.name << ": \"" << message << "\"";
  }
}

TEST(DaylightRecord, RestoresTheSiteTimeAndSkyABakeWasMadeWith) {
  DaylightOptions o;
  o.latitudeDeg = 48.0;
  o.longitudeDeg = 11.5;
  o.timeZone = "Europe/Berlin";
  o.time = "2026-03-01T09:30";
  o.sky = "cie:12";
  o.northAngleDeg = 15.0;
  const LitScene lit = loadLitScene(kPlainModel, o);
  const nlohmann::json record = daylightJson(lit.scene, lit.defaultDaylight);
  const LitScene back = loadLitScene(kPlainModel, {}, record, "manifest.json");
  EXPECT_FALSE(back.defaultDaylight);
  EXPECT_EQ(daylightJson(back.scene, false), record);
  EXPECT_EQ(back.light, lit.light);
  // The default is recorded as such, and a later option overrides the record.
  const LitScene plain = loadLitScene(kPlainModel, {});
  const nlohmann::json defaultRecord = daylightJson(plain.scene, true);
  EXPECT_TRUE(loadLitScene(kPlainModel, {}, defaultRecord, "manifest.json").defaultDaylight);
  DaylightOptions later;
  later.sunDirection = "90,20";
  const LitScene moved = loadLitScene(kPlainModel, later, defaultRecord, "manifest.json");
  EXPECT_FALSE(moved.defaultDaylight);
  EXPECT_EQ(moved.scene.time().sunDirection->azimuthDeg, 90.0);
  // A damaged record names the file.
  nlohmann::json bad = record;
  bad["sky"]["model"] = "foggy";
  try {
    loadLitScene(kPlainModel, {}, bad, "baked/manifest.json");
    ADD_FAILURE() << "a damaged record was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("baked/manifest.json (at /daylight)"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace fly::cli
