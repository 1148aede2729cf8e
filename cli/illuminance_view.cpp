#include "cli/illuminance_view.h"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

#include "base/color.h"
#include "base/math.h"
#include "cli/cairo_png.h"

namespace fly::cli {

void showIlluminance(sdb::Scene& scene) {
  sdb::Material white;
  white.name = "illuminance: white";
  white.diffuseColor = Rgb(1.0f);
  white.reflectionColor = Rgb(0.0f);
  white.emissionLuminance = Rgb(kIlluminanceMarkerCdM2);
  sdb::Material pane;
  pane.name = "illuminance: clear pane";
  pane.diffuseColor = Rgb(0.0f);
  pane.reflectionColor = Rgb(0.0f);
  pane.transmissionColor = Rgb(1.0f);
  pane.transmissionGlossiness = 0.0f;
  const sdb::MaterialId whiteId = scene.addMaterial(white).id;
  const sdb::MaterialId paneId = scene.addMaterial(pane).id;
  std::vector<std::pair<sdb::MeshId, bool>> meshes;
  for (const auto& [id, mesh] : scene.meshes()) {
    meshes.emplace_back(id, scene.material(mesh.material).hasClearTransmission());
  }
  for (const auto& [id, glass] : meshes) scene.setMeshMaterial(id, glass ? paneId : whiteId);
  sdb::SkySettings sky = scene.sky();
  sky.model = sdb::SkyModel::kNone;
  sky.sun = false;
  scene.setSky(sky);
}

std::vector<double> illuminanceFromRender(std::span<const float> rgb) {
  std::vector<double> lux(rgb.size() / 3);
  for (size_t i = 0; i < lux.size(); ++i) {
    const double y = luminance(Rgb(rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]));
    lux[i] = y < 0.5 * kIlluminanceMarkerCdM2 ? NAN : kPi * std::max(0.0, y - kIlluminanceMarkerCdM2);
  }
  return lux;
}

namespace {

int legendColumnPx(int widthPx) {
  return std::max(int(std::lround(0.16 * widthPx)), 160);
}
double legendUnitPx(int widthPx) {
  return legendColumnPx(widthPx) / 190.0;
}  // 1/1200 of a plan's width

}  // namespace

LegendBox illuminanceLegendBox(int widthPx, int heightPx) {
  const double u = legendUnitPx(widthPx);
  const int height = std::max(heightPx, 300);
  return {std::round(widthPx + 30.0 * u), std::round(0.1 * height), std::round(36.0 * u),
          std::round(0.85 * height)};
}

void drawIlluminanceView(const IlluminanceView& v, const std::filesystem::path& pngOut) {
  if (v.widthPx < 1 || v.heightPx < 1 || v.lux.size() != size_t(v.widthPx) * size_t(v.heightPx)) {
    throw std::invalid_argument("drawIlluminanceView: the illuminance does not match the size");
  }
  const int width = v.widthPx + legendColumnPx(v.widthPx);
  const int height = std::max(v.heightPx, 300);
  const std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)> surface(
      cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, height), &cairo_surface_destroy);
  const std::unique_ptr<cairo_t, decltype(&cairo_destroy)> context(cairo_create(surface.get()),
                                                                   &cairo_destroy);
  cairo_t* cr = context.get();
  cairo_set_source_rgb(cr, 1.0, 1.0, 1.0);
  cairo_paint(cr);
  cairo_surface_flush(surface.get());
  unsigned char* data = cairo_image_surface_get_data(surface.get());
  const int stride = cairo_image_surface_get_stride(surface.get());
  for (int y = 0; y < v.heightPx; ++y) {
    auto* row = reinterpret_cast<uint32_t*>(data + y * stride);
    for (int x = 0; x < v.widthPx; ++x) {
      const double lux = v.lux[size_t(y) * size_t(v.widthPx) + size_t(x)];
      const Rgb8 c = std::isfinite(lux) ? falseColour(v.scale.fraction(lux)) : Rgb8{255, 255, 255};
      row[x] = 0xFF000000u | uint32_t(c.r) << 16 | uint32_t(c.g) << 8 | uint32_t(c.b);
    }
  }
  cairo_surface_mark_dirty(surface.get());
  drawFalseColourLegend(cr, v.scale, "lx", illuminanceLegendBox(v.widthPx, v.heightPx),
                        legendUnitPx(v.widthPx));
  writeCairoPng(surface.get(), cr, pngOut, "false-colour view", v.metadata);
}

}  // namespace fly::cli
