// A grid of illuminance sensors over a scene's floors (`fly illuminance --grid HEIGHT,SPACING`), as the
// work-plane grids of daylighting studies: found by tracing, so a two-storey building gets sensors on both
// floors and none under furniture or inside closed solids.
#pragma once

#include <vector>

#include "base/math.h"
#include "raytracer/embree_scene.h"
#include "rdb/trace_rdb.h"

namespace fly::raytracer {

// A floor is any surface whose geometric normal (front face) is within about 25.8° of +Y (n·Y ≥ 0.9): the
// ground, storeys, flat roofs, stair treads and the tops of furniture alike. A pitched roof of 1:2 or steeper
// is not one.
inline constexpr float kFloorMinNormalY = 0.9f;

struct GridSensor {
  vec3 positionM{0.0f};           // on the floor plus heightM·(0, 1, 0)
  vec3 normal{0.0f, 1.0f, 0.0f};  // always up: a horizontal work plane
  float floorHeightM = 0.0f;      // y of the floor below it
};

// The lattice columns over rdb.boundsM in X and Z: per axis max(1, ⌊size / spacing⌋) points spacingM apart,
// centred in the bounds (when the size is a multiple of the spacing the first lies half a spacing from the
// minimum corner). A scene narrower than the spacing gets one column through its centre. Computed in double
// so that a fine spacing over a large scene cannot overflow; 0 for an empty scene. spacingM > 0.
double floorGridColumnCount(const rdb::TraceRdb& rdb, float spacingM);

// Sensors heightM above every floor the lattice's vertical lines cross. Each line is walked down from above
// the scene through all of its hits; an upward-facing hit becomes a sensor when the first surface straight
// above it is none (open sky) or a downward-facing one (a ceiling, the underside of a slab or a table) at
// least heightM away. So nothing stands in a sensor's heightM of air, and a floor whose first surface above
// is the back of an upward-facing one lies inside a closed solid (the ground inside a wall or a box standing
// on it) and gets none. Limits of the rule: a storey modelled as one upward face with no ceiling or underside
// hides the storey below; a wall without a top face (closed by the roof above) has its inside floor gridded.
// Order: by floor height rounded to the millimetre, then z, then x (all ascending). heightM > 0, spacingM >
// 0.
std::vector<GridSensor> floorSensorGrid(const rdb::TraceRdb& rdb, const EmbreeScene& scene, float heightM,
                                        float spacingM);

}  // namespace fly::raytracer
