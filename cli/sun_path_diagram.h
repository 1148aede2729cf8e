// The sun-path diagram of a site, as architects read it (`fly sun ... --path --out sunpath.png`).
//
// Projection: equidistant polar (azimuthal equidistant) — the radius from the centre is proportional to the
// zenith angle, so the zenith is the centre, the horizon the outer circle and the elevation circles are
// evenly spaced. The sky is seen from above, like a site plan: north up, east to the right, south down, west
// left. Drawn: elevation circles every 10° (labelled), azimuth spokes every 15° (labelled every 30°: N, E, S,
// W and degrees clockwise from north), the sun's day arcs on the 21st of each month (months of equal
// declination overlap and share a label; solstices and equinoxes drawn heavier), hour lines (the analemmas of
// each whole hour of local standard time across the year, labelled with the hour), and the chosen instant as
// a dot with its clock time, its date, elevation and azimuth in the caption. Positions are
// sunsky::sunPosition's topocentric azimuth and apparent (refracted) elevation; only what lies above the
// horizon is drawn.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <glm/vec2.hpp>
#include <string>

#include "base/png_metadata.h"
#include "sunsky/sun_position.h"

namespace fly::cli {

struct SunPathRequest {
  // The site, the instant to mark (spa.utc) and the ΔT, pressure and temperature used for every position.
  // The day arcs and hour lines are those of the instant's year in `timeZone`.
  sunsky::SpaInput spa;
  // Time zone of the hour lines and of the marked instant's label: an IANA name ("Europe/Helsinki") or a
  // fixed offset ("+03:00"), as sunsky::parseTime takes it; "" = UTC. Hour lines use the zone's standard
  // time, taken as the smallest UTC offset it has in that year (daylight saving shifts clocks forward, so one
  // hour must be added to read them in summer time); the instant is labelled in clock time, daylight saving
  // included.
  std::string timeZone;
  int sizePx = 1200;  // width and height of the square image in pixels, [300, 8000]
  PngMetadata metadata;  // settings and print resolution in the file (cli/image_metadata.h)
};

// Where the polar diagram lies in an image of sizePx × sizePx pixels. Pixel coordinates: x to the right, y
// down, (0, 0) the top-left corner of the top-left pixel, so pixel (i, j) covers [i, i+1) × [j, j+1).
struct SunPathLayout {
  glm::dvec2 centrePx{0.0};  // the zenith
  double radiusPx = 0.0;     // the horizon circle

  // The point of the sky at `azimuthDeg` (clockwise from north) and `elevationDeg`: radius
  // radiusPx·(90° − elevation)/90°, north up, east right. Negative elevations fall outside the horizon
  // circle.
  glm::dvec2 pixel(double azimuthDeg, double elevationDeg) const;
};

// The layout drawSunPath uses for an image of `sizePx` pixels (title above, caption below the diagram).
SunPathLayout sunPathLayout(int sizePx);

// The fill colour (8-bit sRGB) of the dot that marks the instant; nothing else in the diagram has it.
inline constexpr std::array<uint8_t, 3> kSunPathMarkerRgb{220, 20, 60};

// Draws the diagram and writes it as an RGB PNG, atomically. When the sun is below the horizon at the instant
// (polar night, or simply night) no dot is drawn, and the caption says so and gives the elevation.
// InputError for an invalid site, instant or time zone (from sunsky); std::invalid_argument for sizePx out
// of range; std::runtime_error when drawing or writing fails.
void drawSunPath(const SunPathRequest& request, const std::filesystem::path& pngOut);

}  // namespace fly::cli
