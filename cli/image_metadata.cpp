#include "cli/image_metadata.h"

#include <cstdio>

#include "cli/command.h"

namespace fly::cli {

namespace {

std::string& recorded() {
  static std::string line;
  return line;
}

std::string fixed(double v, int digits) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

}  // namespace

void recordCommandLine(int argc, const char* const* argv) {
  std::string line;
  for (int i = 0; i < argc; ++i) {
    std::string a = argv[i];
    if (a.empty() || a.find_first_of(" \t'\"") != std::string::npos) {
      std::string quoted = "'";
      for (const char c : a) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
      a = quoted + "'";
    }
    line += (i ? " " : "") + a;
  }
  recorded() = line;
}

const std::string& commandLine() {
  return recorded();
}

PngMetadata imageMetadata(const std::string& title, const ImageSettings& settings, double dotsPerInch) {
  PngMetadata m;
  m.text.emplace_back("Title", title);
  m.text.emplace_back("Software", std::string("fly ") + kFlyVersion);
  m.text.emplace_back("fly:command", commandLine());
  m.text.insert(m.text.end(), settings.begin(), settings.end());
  m.dotsPerInch = dotsPerInch;
  return m;
}

ImageSettings daylightSettings(const sdb::Scene& scene) {
  ImageSettings s;
  if (scene.hasSite()) {
    const sdb::Site& site = scene.site();
    s.emplace_back("fly:site", "latitude " + fixed(site.latitudeDeg, 4) + "°, longitude " +
                                   fixed(site.longitudeDeg, 4) + "°, elevation " + fixed(site.elevationM, 0) +
                                   " m, north angle " + fixed(site.northAngleDeg, 1) + "°, time zone " +
                                   site.timeZone);
  }
  const sdb::SiteTime& t = scene.time();
  if (t.sunDirection) {
    s.emplace_back("fly:time", "sun placed at azimuth " + fixed(t.sunDirection->azimuthDeg, 2) +
                                   "°, elevation " + fixed(t.sunDirection->elevationDeg, 2) + "°");
  } else if (!t.localDateTime.empty()) {
    s.emplace_back("fly:time", t.localDateTime);
  }
  const sdb::SkySettings& sky = scene.sky();
  std::string model = sdb::skyModelName(sky.model);
  if (sky.model == sdb::SkyModel::kCie) model += ":" + std::to_string(sky.cieType);
  if (sdb::isClearSky(sky.model)) model += ", turbidity " + fixed(sky.turbidity, 2);
  if (sky.model == sdb::SkyModel::kPerez) model += ", weather " + sky.weatherFile;
  s.emplace_back("fly:sky", model + (sky.sun ? ", sun" : ", no sun"));
  return s;
}

ExrAttributes exrAttributes(const PngMetadata& metadata) {
  ExrAttributes a(metadata.text.begin(), metadata.text.end());
  if (metadata.dotsPerInch > 0.0) a.emplace_back("fly:dpi", fixed(metadata.dotsPerInch, 0));
  return a;
}

void addDpiOption(CLI::App& sub, double* dotsPerInch) {
  sub.add_option("--dpi", *dotsPerInch,
                 "print resolution written into the image file (PNG pHYs chunk, EXR attribute fly:dpi), dots "
                 "per inch, [1, 10000]; the pixel size stays as given")
      ->check(CLI::Range(1.0, 10000.0));
}

}  // namespace fly::cli
