// Surfaces that no view reaches: the inside of closed objects (the inner faces of a closed lamp stem, a floor
// that runs on under a wall block, the back of a two-sided solid's faces). From such a point every direction
// of its hemisphere meets the back of a surface (the side against its counter-clockwise winding's normal)
// before anything else; from any point that the scene's open space sees, some direction meets a front face
// or escapes to the sky. A bake leaves such points out of its error (they would hold it back for light that
// nobody sees) and reports them apart; a light texture's texel anchors itself on a point that is not inside.
#pragma once

#include "base/math.h"
#include "raytracer/embree_scene.h"

namespace fly::raytracer {

// Directions tried, spread over the hemisphere (a spiral of equal solid angles about the normal).
inline constexpr int kEnclosureRays = 16;

// Whether every one of kEnclosureRays rays from p (on a surface, world metres) into the hemisphere of unit
// normal n meets the back of a surface. magnitudeM as EmbreeScene's rayOffsetM takes it (the triangle's
// EmbreeScene::triangleMagnitudeM). rays grows by the rays traced (at most kEnclosureRays).
bool isEnclosed(const EmbreeScene& scene, const vec3& p, const vec3& n, float magnitudeM, uint64_t& rays);

}  // namespace fly::raytracer
