// The scene's outline on a plan: its horizontal section at a height, as architects' floor plans cut the
// building (walls, columns, furniture standing through the cut plane), as segments in plan coordinates.
#pragma once

#include <array>
#include <vector>

#include "base/math.h"
#include "rdb/trace_rdb.h"

namespace fly::cli {

// Where the scene's triangles cross the plane y = heightM (world, metres): one segment per crossing
// triangle, ends as (x, z) in metres. Triangles lying in the plane or touching it at one corner give none; an
// edge lying in the plane is given once, by the triangle above it.
std::vector<std::array<dvec2, 2>> horizontalSection(const rdb::TraceRdb& rdb, double heightM);

}  // namespace fly::cli
