// Surfaces that no view reaches: the inside of closed objects (the inner faces of a closed lamp stem, a floor
// that runs on under a wall block, the back of a two-sided solid's faces). From such a point every direction
// of its hemisphere meets a surface, mostly from its back (the side against its counter-clockwise winding's
// normal); from a point that the scene's open space sees, some direction escapes to the sky or most meet
// fronts (the walls of a closed room face into it). A bake leaves such points out of its error (they would hold it back for light that
// nobody sees) and reports them apart; a light texture's texel anchors itself on a point that is not inside.
#pragma once

#include "base/math.h"
#include "raytracer/embree_scene.h"
#include "rdb/trace_rdb.h"

namespace fly::raytracer {

// Directions tried, spread over the hemisphere (a spiral of equal solid angles about the normal).
inline constexpr int kEnclosureRays = 16;
// Of them, how many must meet a back: 3/4. Solids nest (a stem pushed into a base, a bulb's socket in its
// shade): from inside the outer one, the inner one's outside shows its fronts.
inline constexpr int kEnclosureBackRays = 12;

// An enclosure is small: every ray meets a surface within this share of the scene's diagonal (2.5 %: a
// stem's or wall block's inside, not a hall modelled with its normals facing out, whose inside shows the
// backs of its walls too and which a camera inside sees).
inline constexpr float kEnclosureReachShare = 0.025f;

// kEnclosureReachShare of the diagonal of the box around rdb's vertices, metres.
float enclosureReachM(const rdb::TraceRdb& rdb);

// Whether every one of kEnclosureRays rays from p (on a surface, world metres) into the hemisphere of unit
// normal n meets a surface within reachM, and at least kEnclosureBackRays of them its back. magnitudeM as
// EmbreeScene's rayOffsetM takes it (the triangle's EmbreeScene::triangleMagnitudeM). rays grows by the rays
// traced (at most kEnclosureRays).
bool isEnclosed(const EmbreeScene& scene, const vec3& p, const vec3& n, float magnitudeM, float reachM,
                uint64_t& rays);

}  // namespace fly::raytracer
