// Welding of coincident vertices for baking: exporters often write each quad or face with vertices of its own,
// so that a surface's neighbouring faces share no vertex. Baked apart, the corners of neighbouring faces at one
// point get independent estimates and the surface shows as a patchwork of tiles; charted apart, every face
// becomes a chart. Vertices at the same position (within a tolerance) with equal normals are one point of the
// surface; vertices whose normals differ (a hard edge, a crease) stay apart.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "base/math.h"

namespace fly::rdb {

// Normals within this angle are "equal" for welding: 1°, far below any modelled crease (exporters split
// vertices at creases of 30° or more) and far above float rounding of unit normals.
inline constexpr float kWeldNormalCos = 0.99985f;  // cos 1°

// The weld tolerance of a mesh whose bounding box has this diagonal, metres: 10⁻⁶ of the diagonal (a few
// float ulps of its largest coordinates), at least 10⁻⁹ m.
float weldToleranceM(float boundsDiagonalM);

// For every vertex, the smallest index of the vertices welded with it (itself when none): vertices whose
// positions differ by at most toleranceM in each coordinate and whose unit normals have a cosine of at least
// kWeldNormalCos. Grouping is transitive through chains of such pairs. Non-finite positions or normals are
// never welded. normals is empty (positions alone decide) or one per position. Deterministic.
std::vector<uint32_t> weldCoincidentVertices(std::span<const vec3> positionsM, std::span<const vec3> normals,
                                             float toleranceM);

}  // namespace fly::rdb
