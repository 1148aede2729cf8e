// The storeys of a sensor grid over a building's floors (`--grid`, cli/grid_sensors.h), for one plan per
// storey as architects draw them: the grid's floors grouped by height from the lowest up, each storey taking
// every floor less than kMinStoreyHeightM above its lowest one — a raised slab beside the ground around it,
// steps, a split level and furniture tops stay on the storey they stand on; a floor that high or higher
// begins the next storey. A group with fewer than kMinStoreyShare of the largest storey's sensors (a roof
// ridge, a chimney top, a high shelf) is no storey of its own: it stays with the storey below it.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace fly::cli {

// The least height between two storeys' floors, metres: below the 2.1–2.4 m clear room height building
// codes ask for (e.g. Finland's 2.5 m, England's 2.0 m under stairs), so that no storey can hide in it.
inline constexpr double kMinStoreyHeightM = 2.0;
// The least share of the largest storey's sensors a storey has: a tenth (a first floor over a tenth of the
// ground floor's area is a storey; the few flat spots of a pitched roof are not).
inline constexpr double kMinStoreyShare = 0.1;

struct Storey {
  double lowestFloorM = 0.0;  // its floors' heights (y, metres, world) lie in [lowestFloorM, highestFloorM]
  double highestFloorM = 0.0;
  double mainFloorM = 0.0;      // the floor height (to 1 cm) that carries most of its sensors
  std::vector<size_t> sensors;  // indices into the grid's sensors, in their order
};

// The storeys of sensors standing on floors at floorHeightsM (one per sensor), from the lowest up. Empty for
// no sensors.
std::vector<Storey> gridStoreys(const std::vector<float>& floorHeightsM);

// The storey whose span [its lowest floor, the next storey's lowest floor) holds heightM (metres, world y;
// the highest storey's ends kMinStoreyHeightM above its highest floor). UsageError naming --storey and the
// storeys' main floor heights when none does.
size_t storeyAt(const std::vector<Storey>& storeys, double heightM);

}  // namespace fly::cli
