// `fly info SCENE [--json]`: what a scene contains, its site and the features later stages will build.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "base/brdf_table.h"
#include "base/ggx.h"
#include "cli/baked_manifest.h"
#include "cli/command.h"
#include "cli/scene_daylight.h"
#include "raytracer/embree_scene.h"
#include "raytracer/light_resolution.h"
#include "rdb/trace_rdb_build.h"
#include "sdb/features.h"
#include "sdb/light.h"
#include "sdb/scene_load.h"
#include "sdb/scene_stats.h"

namespace fly::cli {

namespace {

struct InfoOptions {
  std::string scene;
  bool json = false;
  DaylightOptions daylight;
};

// Rounded to the micrometre, so that 0.556f prints as 0.556 and not as its binary expansion.
nlohmann::json vecJson(const vec3& v) {
  const auto um = [](float x) { return std::round(double(x) * 1e6) / 1e6; };
  return nlohmann::json::array({um(v.x), um(v.y), um(v.z)});
}

std::string fixed(double v, int decimals) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(decimals) << v;
  return s.str();
}

std::string vecText(const vec3& v, int decimals) {
  return "(" + fixed(v.x, decimals) + ", " + fixed(v.y, decimals) + ", " + fixed(v.z, decimals) + ")";
}

std::string countsText(const std::map<std::string, size_t>& counts) {
  std::string s;
  for (const auto& [name, n] : counts) s += (s.empty() ? "" : ", ") + name + " " + std::to_string(n);
  return s.empty() ? "" : " (" + s + ")";
}

// The scene's measured BRDFs: each table once (by file), with the SDB's albedo check, and the car paints.
struct MeasuredBrdfs {
  struct Table {
    std::string file;
    BrdfTable::AlbedoPeak peak;
  };
  std::vector<Table> tables;
  size_t carPaints = 0;
};

MeasuredBrdfs measuredBrdfs(const sdb::Scene& scene) {
  MeasuredBrdfs m;
  std::set<std::string> files;
  for (const auto& [id, material] : scene.materials()) {
    if (material.carPaint) ++m.carPaints;
    if (material.measuredBrdf && files.insert(material.measuredBrdfPath).second) {
      m.tables.push_back({material.measuredBrdfPath, material.measuredBrdf->maxAlbedo()});
    }
  }
  return m;
}

// The lights `fly info` lists one by one; a model with more lists only these and counts the rest.
constexpr size_t kMaxListedLights = 20;

// The output of a light in the units that describe it: luminous flux (lm) and intensity (cd, or the
// multiplier of a goniometric file's candela values); for a directional light its illuminance (lux).
nlohmann::json lightJson(const sdb::Light& l) {
  nlohmann::json j = {{"name", l.name}, {"type", sdb::lightTypeName(l.type)}};
  if (l.type == sdb::LightType::kDirectional) {
    j["illuminance_lux"] = luminance(l.color) * l.intensity;
  } else {
    j["flux_lm"] = sdb::luminousFluxLm(l);
    j[l.type == sdb::LightType::kGoniometric ? "candela_multiplier" : "intensity_cd"] = l.intensity;
  }
  j["temperature_k"] = l.temperatureK > 0.0f ? nlohmann::json(l.temperatureK) : nlohmann::json(nullptr);
  if (l.ies) j["file"] = l.iesPath;
  return j;
}

// "bulb: point, 800 lm (63.7 cd), 2700 K".
std::string lightText(const sdb::Light& l) {
  std::string s = l.name + ": " + sdb::lightTypeName(l.type);
  if (l.type == sdb::LightType::kDirectional) {
    s += ", " + fixed(luminance(l.color) * l.intensity, 3) + " lx";
  } else {
    s += ", " + fixed(sdb::luminousFluxLm(l), 1) + " lm (";
    s += l.type == sdb::LightType::kGoniometric
             ? fixed(l.intensity, 4) + " × " + std::filesystem::path(l.iesPath).filename().string()
             : fixed(l.intensity, 2) + " cd";
    s += ")";
  }
  if (l.temperatureK > 0.0f) s += ", " + fixed(l.temperatureK, 0) + " K";
  return s;
}

// "south window: 4.500 m², normal (0.000, 0.000, 1.000)": the normal by the right-hand rule over the corners.
std::string portalText(const sdb::Portal& p) {
  return p.name + ": " + fixed(sdb::portalAreaM2(p), 3) + " m², normal " + vecText(sdb::portalNormal(p), 3) +
         ", " + std::to_string(p.cornersM.size()) + " corners";
}

nlohmann::json portalJson(const sdb::Portal& p) {
  nlohmann::json corners = nlohmann::json::array();
  for (const vec3& c : p.cornersM) corners.push_back(vecJson(c));
  return {{"name", p.name},
          {"area_m2", sdb::portalAreaM2(p)},
          {"normal", vecJson(sdb::portalNormal(p))},
          {"corners_m", corners}};
}

constexpr const char* kChannelNames[3] = {"red", "green", "blue"};

// The anisotropic materials `fly info` lists one by one; a scene with more lists these and counts the rest.
constexpr size_t kMaxListedAnisotropic = 64;

// The name of the texture a material reference reads, or null when there is none.
nlohmann::json textureName(const sdb::Scene& scene, const sdb::TextureRef& ref) {
  return ref ? nlohmann::json(scene.texture(ref.texture).name) : nlohmann::json(nullptr);
}

// An anisotropic material's lobe as both engines shape it (base/ggx.h, ggxAnisotropicAlphas): the SDB's U, V,
// glossiness and rotation, the GGX widths they give along U and V, and the textures that replace them per
// texel (the constants are then the largest glossiness and U).
nlohmann::json anisotropyJson(const sdb::Scene& scene, const sdb::Material& m) {
  const vec2 widths =
      ggxAnisotropicAlphas(m.reflectionGlossiness * m.reflectionGlossiness, m.anisotropyU, m.anisotropyV);
  return {{"material", m.name},
          {"anisotropy_u", m.anisotropyU},
          {"anisotropy_v", m.anisotropyV},
          {"glossiness", m.reflectionGlossiness},
          {"ggx_alpha_u", widths.x},
          {"ggx_alpha_v", widths.y},
          {"rotation_deg", radToDeg(m.anisotropyRotationRad)},
          {"anisotropy_texture", textureName(scene, m.anisotropyTexture)},
          {"rotation_texture", textureName(scene, m.anisotropyRotationTexture)},
          {"glossiness_texture", textureName(scene, m.reflectionGlossinessTexture)}};
}

// "Brushed: GGX α 0.8275 along U, 0.2500 along V (glossiness 0.6754, U 0.8148, V 0.0000); U turned 30.00°
// from the tangent", with "per texel ('texture')" for what a texture gives.
std::string anisotropyText(const sdb::Scene& scene, const sdb::Material& m) {
  const auto texture = [&](const sdb::TextureRef& ref) {
    return "'" + scene.texture(ref.texture).name + "'";
  };
  std::string s = m.name + ": ";
  if (m.anisotropyTexture || m.reflectionGlossinessTexture) {
    s += "U, V " + (m.anisotropyTexture ? "per texel (" + texture(m.anisotropyTexture) + ")"
                                        : fixed(m.anisotropyU, 4) + ", " + fixed(m.anisotropyV, 4));
    s += ", glossiness " + (m.reflectionGlossinessTexture
                                ? "per texel up to " + fixed(m.reflectionGlossiness, 4) + " (" +
                                      texture(m.reflectionGlossinessTexture) + ")"
                                : fixed(m.reflectionGlossiness, 4));
  } else {
    const vec2 widths =
        ggxAnisotropicAlphas(m.reflectionGlossiness * m.reflectionGlossiness, m.anisotropyU, m.anisotropyV);
    s += "GGX α " + fixed(widths.x, 4) + " along U, " + fixed(widths.y, 4) + " along V (glossiness " +
         fixed(m.reflectionGlossiness, 4) + ", U " + fixed(m.anisotropyU, 4) + ", V " +
         fixed(m.anisotropyV, 4) + ")";
  }
  s += "; U turned " +
       (m.anisotropyRotationTexture ? "per texel (" + texture(m.anisotropyRotationTexture) + ")"
                                    : fixed(radToDeg(m.anisotropyRotationRad), 2) + "°") +
       " from the tangent";
  return s;
}

nlohmann::json infoJson(const sdb::Scene& scene, const sdb::SceneStats& st, const sdb::SceneFeatures& f,
                        const LitScene& lit) {
  nlohmann::json j;
  j["file"] = scene.sourcePath.string();
  j["nodes"] = st.nodes;
  j["meshes"] = st.meshes;
  j["mesh_instances"] = st.meshInstances;
  j["triangles"] = st.triangles;
  j["vertices"] = st.vertices;
  j["textures"] = st.textures;
  j["materials"] = {{"total", st.materials}, {"by_class", st.materialsByClass}};
  j["lights"] = {{"total", st.lights}, {"by_type", st.lightsByType}, {"emissive_meshes", st.emissiveMeshes}};
  nlohmann::json lights = nlohmann::json::array();
  for (const auto& [id, l] : scene.lights()) lights.push_back(lightJson(l));
  j["lights"]["list"] = lights;
  nlohmann::json portals = nlohmann::json::array();
  for (const sdb::Portal& p : scene.portals()) portals.push_back(portalJson(p));
  j["portals"] = portals;
  nlohmann::json cameras = nlohmann::json::array();
  for (const auto& [id, c] : scene.cameras()) cameras.push_back(c.name);
  j["cameras"] = cameras;
  if (st.boundsWorldM.empty()) {
    j["bounds_m"] = nullptr;
  } else {
    j["bounds_m"] = {{"min", vecJson(st.boundsWorldM.min)},
                     {"max", vecJson(st.boundsWorldM.max)},
                     {"size", vecJson(st.boundsWorldM.size())}};
  }
  if (scene.hasSite()) {
    const sdb::Site& s = scene.site();
    j["site"] = {{"latitude_deg", s.latitudeDeg},      {"longitude_deg", s.longitudeDeg},
                 {"elevation_m", s.elevationM},        {"time_zone", s.timeZone},
                 {"north_angle_deg", s.northAngleDeg}, {"grid", sdb::gridName(s)}};
  } else {
    j["site"] = nullptr;
  }
  j["time"] = scene.time().localDateTime.empty() ? nlohmann::json(nullptr)
                                                 : nlohmann::json(scene.time().localDateTime);
  if (const std::optional<sdb::SunDirection>& d = scene.time().sunDirection) {
    j["sun_direction"] = {{"azimuth_deg", d->azimuthDeg}, {"elevation_deg", d->elevationDeg}};
  } else {
    j["sun_direction"] = nullptr;
  }
  j["sky"] = {{"model", sdb::skyModelName(scene.sky().model)}, {"sun", scene.sky().sun}};
  if (scene.sky().model == sdb::SkyModel::kCie) j["sky"]["cie_type"] = scene.sky().cieType;
  if (sdb::isClearSky(scene.sky().model) || scene.sky().sun) j["sky"]["turbidity"] = scene.sky().turbidity;
  if (scene.sky().model != sdb::SkyModel::kNone || scene.sky().sun) j["sky"]["ground_albedo"] = scene.sky().groundAlbedo;
  j["light"] = {{"default_daylight", lit.defaultDaylight}, {"description", lit.light}};
  j["features"] = f.names();
  j["engine_reflections"] = f.engineReflections;
  if (f.anisotropicMaterials) {
    nlohmann::json list = nlohmann::json::array();
    for (const auto& [id, m] : scene.materials()) {
      if (m.isAnisotropic()) list.push_back(anisotropyJson(scene, m));
    }
    j["anisotropic_materials"] = list;
  }
  if (f.measuredBrdfs) {
    const MeasuredBrdfs m = measuredBrdfs(scene);
    nlohmann::json tables = nlohmann::json::array();
    for (const MeasuredBrdfs::Table& t : m.tables) {
      tables.push_back({{"file", t.file},
                        {"max_albedo", t.peak.albedo},
                        {"max_albedo_theta_in_deg", t.peak.thetaInDeg},
                        {"max_albedo_channel", kChannelNames[t.peak.channel]}});
    }
    j["measured_brdfs"] = {{"tables", tables}, {"car_paints", m.carPaints}};
  }
  return j;
}

void printText(const sdb::Scene& scene, const sdb::SceneStats& st, const sdb::SceneFeatures& f,
               const LitScene& lit) {
  std::ostringstream o;
  o << "scene      " << scene.sourcePath.string() << "\n";
  o << "nodes      " << st.nodes << "\n";
  o << "meshes     " << st.meshes << " (" << st.meshInstances << " placed)\n";
  o << "triangles  " << st.triangles << " (" << st.vertices << " vertices)\n";
  o << "materials  " << st.materials << countsText(st.materialsByClass) << "\n";
  o << "textures   " << st.textures << "\n";
  o << "lights     " << st.lights << countsText(st.lightsByType);
  if (st.emissiveMeshes > 0)
    o << ", and " << st.emissiveMeshes << " emissive mesh" << (st.emissiveMeshes > 1 ? "es" : "");
  o << "\n";
  size_t listed = 0;
  for (const auto& [id, l] : scene.lights()) {
    if (listed++ == kMaxListedLights) {
      o << "           … and " << scene.lights().size() - kMaxListedLights << " more\n";
      break;
    }
    o << "           " << lightText(l) << "\n";
  }
  if (!scene.portals().empty()) {
    o << "portals    " << scene.portals().size() << " declared\n";
    for (const sdb::Portal& p : scene.portals()) o << "           " << portalText(p) << "\n";
  }
  o << "cameras    " << st.cameras;
  std::string names;
  for (const auto& [id, c] : scene.cameras()) names += (names.empty() ? "" : ", ") + c.name;
  o << (names.empty() ? "" : " (" + names + ")") << "\n";
  if (st.boundsWorldM.empty()) {
    o << "bounds     empty\n";
  } else {
    o << "bounds     " << vecText(st.boundsWorldM.min, 3) << " to " << vecText(st.boundsWorldM.max, 3)
      << " m, size " << vecText(st.boundsWorldM.size(), 3) << " m\n";
  }
  if (scene.hasSite()) {
    const sdb::Site& s = scene.site();
    o << "site       " << fixed(std::abs(s.latitudeDeg), 4) << "° " << (s.latitudeDeg >= 0 ? "N" : "S")
      << ", " << fixed(std::abs(s.longitudeDeg), 4) << "° " << (s.longitudeDeg >= 0 ? "E" : "W") << ", "
      << fixed(s.elevationM, 1) << " m, time zone " << s.timeZone << ", north " << fixed(s.northAngleDeg, 1)
      << "° from -Z" << (s.grid == sdb::Site::Grid::kNone ? "" : ", grid " + sdb::gridName(s)) << "\n";
  } else {
    o << "site       none\n";
  }
  if (const std::optional<sdb::SunDirection>& d = scene.time().sunDirection) {
    o << "time       none; sun placed at " << fixed(d->elevationDeg, 1) << "° elevation, azimuth "
      << fixed(d->azimuthDeg, 1) << "°\n";
  } else {
    o << "time       " << (scene.time().localDateTime.empty() ? "none" : scene.time().localDateTime) << "\n";
  }
  o << "sky        " << sdb::skyModelName(scene.sky().model);
  if (scene.sky().model == sdb::SkyModel::kCie) o << " type " << scene.sky().cieType;
  o << ", sun " << (scene.sky().sun ? "on" : "off") << "\n";
  o << "light      " << lit.light << "\n";
  std::string feats;
  for (const std::string& n : f.names()) feats += (feats.empty() ? "" : " ") + n;
  o << "features   " << (feats.empty() ? "none" : feats) << "\n";
  for (const auto& [material, choice] : f.engineReflections) o << "reflection " << material << ": " << choice << "\n";
  size_t anisotropic = 0;
  for (const auto& [id, m] : scene.materials()) {
    if (!m.isAnisotropic()) continue;
    if (anisotropic++ < kMaxListedAnisotropic) o << "anisotropy " << anisotropyText(scene, m) << "\n";
  }
  if (anisotropic > kMaxListedAnisotropic) {
    o << "           … and " << anisotropic - kMaxListedAnisotropic << " more anisotropic materials\n";
  }
  if (f.measuredBrdfs) {
    // Each table's largest directional albedo: above 1 the baker scales the table down (docs/measured-brdf.md).
    const MeasuredBrdfs m = measuredBrdfs(scene);
    o << "brdfs      " << m.tables.size() << " measured table" << (m.tables.size() == 1 ? "" : "s") << ", "
      << m.carPaints << " car paint" << (m.carPaints == 1 ? "" : "s") << "\n";
    for (const MeasuredBrdfs::Table& t : m.tables) {
      o << "           " << t.file << ": albedo up to " << fixed(t.peak.albedo, 3) << " (" << kChannelNames[t.peak.channel]
        << ", at " << fixed(t.peak.thetaInDeg, 0) << "°)"
        << (t.peak.albedo > 1.0f ? ", above 1: the baker scales it down to 1" : "") << "\n";
    }
  }
  std::cout << o.str();
}

// What a bake gives each object with triangles: a light texture asked for, one the bake adds where vertices
// cannot carry the light (raytracer/light_resolution.h, and why), or vertex light maps alone.
struct LightMapPlanEntry {
  std::string name;
  std::string gets;  // "light texture", "light texture (automatic)", "vertex light map"
  std::string why;
};
std::vector<LightMapPlanEntry> lightMapPlan(const sdb::Scene& scene) {
  rdb::TraceRdb rdb = rdb::buildTraceRdb(scene);
  const raytracer::EmbreeScene embree(rdb);
  raytracer::LightResolutionSettings settings;
  settings.texelsPerMetre = float(scene.bakeSettings().texelsPerMetre);
  const std::vector<raytracer::MeshLightResolution> analysis = raytracer::addNeededLightTextures(rdb, embree, settings);
  std::vector<LightMapPlanEntry> plan;
  for (const rdb::TraceMesh& m : rdb.meshes) {
    if (m.triangleCount == 0) continue;
    LightMapPlanEntry e;
    e.name = scene.mesh(sdb::MeshId{m.sdbMeshId}).name;
    if (e.name.empty()) e.name = scene.node(sdb::NodeId{m.sdbNodeId}).name;
    if (m.lightTexture == rdb::TraceMesh::kNoLightTexture) {
      e.gets = "vertex light map";
      e.why = m.automaticLightTextureAllowed ? "its vertices carry the light" : "\"lightTexture\": false";
    } else if (rdb.lightTextures[m.lightTexture].automatic) {
      e.gets = "light texture (automatic)";
      e.why = rdb.lightTextures[m.lightTexture].automaticReason;
    } else {
      e.gets = "light texture";
      e.why = "asked for in the scene file";
    }
    plan.push_back(std::move(e));
  }
  return plan;
}

}  // namespace

Command addInfoCommand(CLI::App& app) {
  auto opts = std::make_shared<InfoOptions>();
  CLI::App* sub =
      app.add_subcommand("info", "Print what a scene contains: counts, bounds (m), site, features");
  sub->add_option("SCENE", opts->scene,
                  "scene file (.json), glTF model (.gltf, .glb) or baked scene directory")
      ->required();
  sub->add_flag("--json", opts->json, "print one JSON object instead of text (default: text)");
  opts->daylight.add(*sub);
  return {sub, [opts]() {
            // A baked scene directory: the scene it was baked from (materials, lights, cameras, site and
            // time, as the GL engine shows it) and what the manifest says of the bake; when that scene is
            // gone, the baked geometry (scene.gltf), whose materials are matte and which has no lights or
            // cameras.
            std::optional<nlohmann::json> bake;
            bool sourceFound = true;
            std::filesystem::path path = opts->scene;
            nlohmann::json bakedDaylight;
            std::string manifestPath;
            if (isBakedScene(path)) {
              bake = readBakedManifest(path);
              manifestPath = (path / "manifest.json").string();
              if (const std::optional<std::filesystem::path> source = findBakedSourceScene(path, *bake)) {
                path = *source;
                bakedDaylight = bake->value("daylight", nlohmann::json());
              } else {
                sourceFound = false;
                path /= "scene.gltf";
              }
            }
            // The baked geometry alone (its scene file gone) is described without light.
            const LitScene lit = sourceFound ? loadLitScene(path, opts->daylight, bakedDaylight, manifestPath)
                                             : LitScene{sdb::loadScene(path), false, "none (the scene file is gone)"};
            const sdb::Scene& scene = lit.scene;
            const sdb::SceneStats stats = sdb::computeStats(scene);
            const sdb::SceneFeatures features = sdb::computeFeatures(scene);
            // Before a bake: what each object would get (after one, the manifest says what it got).
            std::vector<LightMapPlanEntry> plan;
            if (!bake) plan = lightMapPlan(scene);
            if (opts->json) {
              nlohmann::json j = infoJson(scene, stats, features, lit);
              if (bake) {
                j["bake"] = bakeSummaryJson(*bake);
                j["bake"]["source_scene_found"] = sourceFound;
              } else {
                j["light_maps"] = nlohmann::json::array();
                for (const LightMapPlanEntry& e : plan)
                  j["light_maps"].push_back({{"object", e.name}, {"gets", e.gets}, {"why", e.why}});
              }
              std::cout << j.dump(2) << "\n";
            } else {
              printText(scene, stats, features, lit);
              if (bake) std::cout << bakeSummaryText(*bake, sourceFound);
              // Objects with light textures one by one; those with vertex maps alone counted.
              size_t vertexOnly = 0;
              for (const LightMapPlanEntry& e : plan) {
                if (e.gets == "vertex light map") {
                  ++vertexOnly;
                  continue;
                }
                std::cout << "light map  \"" << e.name << "\": " << e.gets << ", " << e.why << "\n";
              }
              if (vertexOnly > 0) {
                std::cout << "light map  " << vertexOnly << " other object" << (vertexOnly == 1 ? "" : "s")
                          << ": vertex light maps\n";
              }
            }
            return 0;
          }};
}

}  // namespace fly::cli
