// A sky portal declared in the scene file: an opening in closed geometry (a window hole without glass, a
// door left open) through which the sky lights an interior. Portals are no geometry: rays pass them, no
// engine draws them; the baker aims part of its sky samples through them (raytracer/integrator.h, "Sky
// portals"), as it does through clear glass, which needs no declaration.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "base/math.h"

namespace fly::sdb {

// The portal's plane: the fourth corner of a quad may lie off the plane of the first three by at most this
// fraction of the quad's longest edge.
inline constexpr double kPortalPlanarityTolerance = 1e-3;
// Portals of a smaller area (m²) are degenerate.
inline constexpr double kPortalMinAreaM2 = 1e-6;

struct Portal {
  std::string name;
  // World frame, metres: 3 corners (a triangle) or 4 (a planar convex quad), in order around the edge.
  std::vector<vec3> cornersM;
};

// What is wrong with a portal's corners: the corner at fault (or none, for the whole), what and how to fix
// it.
struct PortalProblem {
  std::optional<size_t> corner;
  std::string message;
  std::string hint;
};

// nullopt when `cornersM` is a valid portal: 3 or 4 finite corners enclosing at least kPortalMinAreaM2, and
// for 4 corners a quad whose fourth corner lies within kPortalPlanarityTolerance × its longest edge of the
// plane of the first three and that turns the same way at every corner (convex, no three corners on a line).
std::optional<PortalProblem> checkPortal(std::span<const vec3> cornersM);

// The portal as triangles, 3 corners each in the world frame: (0, 1, 2), and for a quad also (0, 2, 3).
std::vector<vec3> portalTrianglesM(const Portal& portal);

// The portal's area in m² (the sum of its triangles').
double portalAreaM2(const Portal& portal);

// The unit normal of the portal's plane by the right-hand rule over its corner order: counter-clockwise
// corners seen from a side face that side.
vec3 portalNormal(const Portal& portal);

}  // namespace fly::sdb
