// Iso-lines of a sampled scalar field on a regular lattice by marching squares (Lorensen & Cline's marching
// cubes in two dimensions): within each square of four samples the line crosses the edges whose ends lie on
// either side of the level, at the point found by linear interpolation along the edge. A saddle square (two
// opposite corners above) is resolved by the mean of its corners (Nielson & Hamann's asymptotic decider in
// its simplest form), so that lines never cross.
#pragma once

#include <array>
#include <vector>

#include "base/math.h"

namespace fly::cli {

// Samples on a columns × rows lattice, row-major; NaN where there is no sample (no floor there): squares
// with a missing corner get no line.
struct ScalarGrid {
  int columns = 0;
  int rows = 0;
  std::vector<double> values;  // columns · rows

  double at(int column, int row) const { return values[size_t(row) * size_t(columns) + size_t(column)]; }
};

// The segments of the iso-line at `level`, ends in lattice coordinates (column, row) as fractions. A sample
// equal to the level counts as above it.
std::vector<std::array<dvec2, 2>> isoContours(const ScalarGrid& grid, double level);

}  // namespace fly::cli
