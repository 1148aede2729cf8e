#include "cli/environment_option.h"

#include <CLI/CLI.hpp>

#include <cmath>
#include <fstream>
#include <iterator>
#include <sstream>
#include <vector>

#include "base/error.h"
#include "base/math.h"
#include "cli/image_decoder_module.h"
#include "cli/studio_environment.h"

namespace fly::cli {
namespace {

// Decoded floats an environment may take (a 16384 × 8192 panorama is 1.6 GB): 1 GiB.
constexpr size_t kMaxEnvironmentBytes = size_t(1) << 30;

std::vector<uint8_t> readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError({path}, "cannot be opened", "check the path given to --environment");
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw InputError({path}, "cannot be read");
  return bytes;
}

}  // namespace

void addEnvironmentOptions(CLI::App& sub, EnvironmentOptions& o) {
  sub.add_option("--environment", o.source,
                 "sunlight mode's environment in place of the sky and sun: an equirectangular .exr or .hdr "
                 "panorama in cd/m² (+Y up), or 'studio' (a grey dome with three softboxes for products)");
  sub.add_option("--environment-scale", o.scale,
                 "multiplies the --environment file's values into cd/m² (default 1: the file is in cd/m²)");
}

std::optional<rdb::RasterSky> loadEnvironment(const EnvironmentOptions& o) {
  if (!(o.scale > 0.0) || !std::isfinite(o.scale)) throw UsageError("--environment-scale must be a finite number > 0");
  if (o.source.empty()) {
    if (o.scale != 1.0) throw UsageError("--environment-scale needs --environment FILE");
    return std::nullopt;
  }
  if (o.source == "studio") {
    if (o.scale != 1.0) throw UsageError("--environment-scale applies to a file, not to the studio environment");
    return studioEnvironment();
  }
  const std::vector<uint8_t> bytes = readBytes(o.source);
  sdb::FloatRgbImage image;
  try {
    image = decodeFloatImageThroughModule(bytes, kMaxEnvironmentBytes);
  } catch (const std::runtime_error& e) {
    throw InputError({o.source}, std::string("cannot be used as an environment: ") + e.what(),
                     "give an equirectangular Radiance HDR (.hdr) or OpenEXR (.exr) panorama");
  }
  rdb::RasterSky sky;
  sky.width = uint32_t(image.width);
  sky.height = uint32_t(image.height);
  sky.radianceCdM2.resize(size_t(sky.width) * sky.height);
  for (size_t p = 0; p < sky.radianceCdM2.size(); ++p) {
    Rgb v;
    for (int c = 0; c < 3; ++c) {
      const double x = double(image.rgb[3 * p + size_t(c)]) * o.scale;
      if (!(x >= 0.0) || !std::isfinite(x) || x > 1e30) {
        std::ostringstream s;
        s << "pixel (" << p % sky.width << ", " << p / sky.width << ") has the value " << image.rgb[3 * p + size_t(c)]
          << " in channel " << "RGB"[c] << (o.scale != 1.0 ? " (before --environment-scale)" : "")
          << ": radiance must be finite and ≥ 0";
        throw InputError({o.source}, s.str(), "repair or re-export the panorama");
      }
      v[c] = float(x);
    }
    sky.radianceCdM2[p] = v;
  }
  return sky;
}

void applyEnvironment(rdb::RasterRdb& rdb, const rdb::RasterSky& environment) {
  rdb.sky = environment;
  rdb.variants.sky = true;
  rdb.variants.sun = false;
  // Horizontal illuminance of each hemisphere, E = Σ L cos θ ΔΩ over the pixels (ΔΩ = Δφ (cos θ₀ − cos θ₁)).
  Rgb upLux(0.0f), downLux(0.0f);
  const double dPhi = 2.0 * kPi / environment.width;
  for (uint32_t y = 0; y < environment.height; ++y) {
    const double c0 = std::cos(kPi * y / environment.height), c1 = std::cos(kPi * (y + 1) / environment.height);
    const double cosMid = std::cos(kPi * (y + 0.5) / environment.height);
    const float weight = float(std::abs(cosMid) * dPhi * (c0 - c1));
    Rgb& e = cosMid >= 0.0 ? upLux : downLux;
    for (uint32_t x = 0; x < environment.width; ++x) e += weight * environment.radianceCdM2[size_t(y) * environment.width + x];
  }
  rdb.daylightAmbient = {upLux, downLux};
}

std::string environmentLine(const EnvironmentOptions& o, const std::optional<rdb::RasterSky>& environment) {
  if (!environment) return "";
  std::ostringstream s;
  s << "env       " << o.source << " (" << environment->width << "×" << environment->height << " px";
  if (o.scale != 1.0) s << ", scale " << o.scale;
  s << ", in place of the scene's sky and sun in sunlight mode)\n";
  return s.str();
}

}  // namespace fly::cli
