#include "cli/baked_manifest.h"

#include <iomanip>
#include <sstream>
#include <vector>

#include "base/error.h"
#include "base/file_io.h"

namespace fly::cli {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr const char* kHintRebake =
    "the manifest is damaged or not from fly bake: bake the scene again with fly bake";

enum class Kind { kString, kUnsigned, kNumber, kBoolean, kObject, kArray };

bool hasKind(const json& v, Kind kind) {
  switch (kind) {
    case Kind::kString:
      return v.is_string();
    case Kind::kUnsigned:
      return v.is_number_unsigned();
    case Kind::kNumber:
      return v.is_number();
    case Kind::kBoolean:
      return v.is_boolean();
    case Kind::kObject:
      return v.is_object();
    case Kind::kArray:
      return v.is_array();
  }
  return false;
}

const char* kindName(Kind kind) {
  switch (kind) {
    case Kind::kString:
      return "a string";
    case Kind::kUnsigned:
      return "an unsigned integer";
    case Kind::kNumber:
      return "a number";
    case Kind::kBoolean:
      return "true or false";
    case Kind::kObject:
      return "an object";
    case Kind::kArray:
      return "an array";
  }
  return "";
}

// Throws unless `object[key]` has `kind`; a missing key is accepted when `optional`.
void require(const json& object, const char* key, Kind kind, const std::string& fileName,
             const std::string& at, bool optional = false) {
  const auto it = object.find(key);
  if (it == object.end() && optional) return;
  if (it == object.end() || !hasKind(*it, kind)) {
    throw InputError({fileName, 0, 0, at + "/" + key},
                     std::string("needs \"") + key + "\", " + kindName(kind), kHintRebake);
  }
}

std::string fixed(double v, int decimals) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(decimals) << v;
  return s.str();
}

// The objects' light textures: object index, name, files, size and density.
json lightTexturesJson(const json& m) {
  json list = json::array();
  const json& objects = m.at("objects");
  for (size_t i = 0; i < objects.size(); ++i) {
    if (!objects[i].contains("light_texture")) continue;
    json t = objects[i].at("light_texture");
    t["object"] = i;
    t["name"] = objects[i].value("mesh_name", "").empty() ? objects[i].value("node_name", "")
                                                          : objects[i].value("mesh_name", "");
    list.push_back(std::move(t));
  }
  return list;
}

}  // namespace

bool isBakedScene(const fs::path& dir) {
  std::error_code ec;
  return fs::is_directory(dir, ec) && fs::is_regular_file(dir / "manifest.json", ec);
}

json parseBakedManifest(std::string_view text, const std::string& fileName) {
  json manifest = json::parse(text, nullptr, false);
  if (manifest.is_discarded() || !manifest.is_object()) {
    throw InputError({fileName}, "is not valid JSON", "bake the scene again with fly bake");
  }
  if (manifest.value("format", json()) != kBakedSceneFormat) {
    throw InputError({fileName, 0, 0, "/format"}, "is not a fly baked-scene manifest",
                     "give the directory that fly bake --out wrote");
  }
  const json version = manifest.value("format_version", json());
  if (!version.is_number_integer() || version != kBakedSceneFormatVersion) {
    throw InputError({fileName, 0, 0, "/format_version"},
                     "has format version " + version.dump() + "; this fly reads version " +
                         std::to_string(kBakedSceneFormatVersion),
                     "bake the scene again with this fly");
  }
  require(manifest, "scene", Kind::kString, fileName, "");
  require(manifest, "fly_version", Kind::kString, fileName, "");
  require(manifest, "samples_per_vertex", Kind::kUnsigned, fileName, "");
  require(manifest, "rays", Kind::kUnsigned, fileName, "");
  require(manifest, "bake_seconds", Kind::kNumber, fileName, "");
  require(manifest, "relative_error_p95", Kind::kNumber, fileName, "");
  require(manifest, "objects", Kind::kArray, fileName, "");
  const json& objects = manifest["objects"];
  for (size_t k = 0; k < objects.size(); ++k) {
    const std::string at = "/objects/" + std::to_string(k);
    if (!objects[k].is_object()) throw InputError({fileName, 0, 0, at}, "is not an object", kHintRebake);
    require(objects[k], "mesh_name", Kind::kString, fileName, at, true);
    require(objects[k], "node_name", Kind::kString, fileName, at, true);
    require(objects[k], "light_texture", Kind::kObject, fileName, at, true);
    if (const auto t = objects[k].find("light_texture"); t != objects[k].end()) {
      const std::string tAt = at + "/light_texture";
      require(*t, "width", Kind::kUnsigned, fileName, tAt);
      require(*t, "height", Kind::kUnsigned, fileName, tAt);
      require(*t, "texels_per_metre", Kind::kNumber, fileName, tAt);
      require(*t, "front", Kind::kString, fileName, tAt);
      require(*t, "back", Kind::kString, fileName, tAt, true);
      require(*t, "automatic", Kind::kBoolean, fileName, tAt, true);
      require(*t, "automatic_reason", Kind::kString, fileName, tAt, true);
    }
  }
  return manifest;
}

json readBakedManifest(const fs::path& dir) {
  const fs::path path = dir / "manifest.json";
  return parseBakedManifest(readInputFile(path, "baked scene manifest"), path.string());
}

std::optional<fs::path> findBakedSourceScene(const fs::path& dir, const json& manifest) {
  std::vector<fs::path> candidates;
  if (manifest.contains("scene_from_bake") && manifest["scene_from_bake"].is_string() &&
      !manifest["scene_from_bake"].get<std::string>().empty())
    candidates.push_back(dir / manifest["scene_from_bake"].get<std::string>());
  if (manifest.contains("scene_absolute") && manifest["scene_absolute"].is_string())
    candidates.emplace_back(manifest["scene_absolute"].get<std::string>());
  if (manifest.contains("scene") && manifest["scene"].is_string()) {
    const fs::path recorded = manifest["scene"].get<std::string>();
    candidates.push_back(recorded);
    if (recorded.is_relative()) candidates.push_back(dir.parent_path() / recorded);
  }
  for (const fs::path& c : candidates) {
    std::error_code ec;
    if (fs::is_regular_file(c, ec)) return c;
  }
  return std::nullopt;
}

json bakeSummaryJson(const json& m) {
  return {{"scene", m.at("scene")},
          {"samples_per_vertex", m.at("samples_per_vertex")},
          {"relative_error_p95", m.at("relative_error_p95")},
          {"bake_seconds", m.at("bake_seconds")},
          {"rays", m.at("rays")},
          {"objects", m.at("objects").size()},
          {"light_textures", lightTexturesJson(m)},
          {"sun_direct", m.value("sun_direct", json())},
          {"fly_version", m.at("fly_version")}};
}

std::string bakedSunTime(const json& m) {
  const json sun = m.value("sun_direct", json());
  if (!sun.is_object()) return "";
  const json time = sun.value("time", json());
  if (time.is_string() && !time.get<std::string>().empty()) {
    std::string t = time.get<std::string>();  // 2026-06-21T15:00
    if (t.size() > 10 && t[10] == 'T') t[10] = ' ';
    const json zone = sun.value("time_zone", json());
    return zone.is_string() && !zone.get<std::string>().empty() ? t + " " + zone.get<std::string>() : t;
  }
  const json placed = sun.value("sun_direction", json());
  if (placed.is_object() && placed.value("azimuth_deg", json()).is_number() &&
      placed.value("elevation_deg", json()).is_number()) {
    return "the sun placed at azimuth " + fixed(placed["azimuth_deg"].get<double>(), 1) + "°, elevation " +
           fixed(placed["elevation_deg"].get<double>(), 1) + "°";
  }
  return "the bake's sun";
}

std::string bakedSunlightText(const json& m) {
  const std::string time = bakedSunTime(m);
  if (time.empty()) {
    return "note: this bake keeps no separate sun-direct light (baked without a sun, or by a fly before it "
           "was kept apart): sunlight mode shows the baked light as light-map mode does, under the bake's "
           "sun; "
           "bake again to move the sun";
  }
  const json& sun = m.at("sun_direct");
  std::string text = "indirect light baked at " + time;
  if (sun.value("elevation_deg", json()).is_number() &&
      sun.value("normal_illuminance_luminance_lux", json()).is_number()) {
    text += " (sun at " + fixed(sun["elevation_deg"].get<double>(), 1) + "° elevation, " +
            fixed(sun["normal_illuminance_luminance_lux"].get<double>(), 0) + " lx)";
  }
  return text + "; the sun's direct light is drawn for the time rendered";
}

std::string bakeSummaryText(const json& m, bool sourceFound) {
  std::ostringstream o;
  o << "baked from " << m.at("scene").get<std::string>() << " by fly "
    << m.at("fly_version").get<std::string>() << "\n";
  if (!sourceFound) {
    o << "warning    that scene file no longer exists: above is the baked geometry only (matte materials, no "
         "lights, cameras or site); fly render and fly view need the scene file back at that path\n";
  }
  o << "bake       " << m.at("samples_per_vertex").get<uint64_t>()
    << " samples per vertex, 95th percentile of "
    << "relative standard error " << fixed(100.0 * m.at("relative_error_p95").get<double>(), 2) << " %, "
    << fixed(m.at("bake_seconds").get<double>(), 1) << " s, " << m.at("objects").size() << " objects\n";
  for (const json& t : lightTexturesJson(m)) {
    o << "light tex  object " << t.at("object").get<size_t>() << " \"" << t.at("name").get<std::string>()
      << "\": " << t.at("width").get<uint32_t>() << " x " << t.at("height").get<uint32_t>() << " texels, "
      << fixed(t.at("texels_per_metre").get<double>(), 1) << " texels/m"
      << (!t.value("automatic", false)             ? ""
          : t.contains("automatic_reason") ? " (automatic: " + t.at("automatic_reason").get<std::string>() + ")"
                                           : std::string(" (automatic)"))
      << ", " << t.at("front").get<std::string>()
      << (t.contains("back") ? " + back" : "") << "\n";
  }
  o << "sunlight   " << bakedSunlightText(m) << "\n";
  return o.str();
}

}  // namespace fly::cli
