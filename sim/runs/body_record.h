// The flagellum's body per sample of a run's timeseries.csv, as points in
// the head's frame [mm] (head, tip 1, ..., tip n): realised from the
// recorded tips, and ideal: the discretised wave as the realised body
// would draw it. For a closed-loop run segment k keeps the realised body's
// mean length from point k-1 to tip k and turns from segment k-1 (the
// head's axis for k = 1) by asin(reference_k / L_k), L_k the length that
// maps the measured deflection onto the realised turn angle (least
// squares); for a gait the turn is joint k's reference angle. The tips
// stand in for the hinges.
#pragma once

#include <vector>

#include "sim/io/csv.h"

namespace ipmc {

struct BodyPoint {
  double x = 0.0, y = 0.0;
};

struct BodyRecord {
  std::vector<double> t_s;
  std::vector<std::vector<BodyPoint>> realised;
  std::vector<std::vector<BodyPoint>> ideal;  // empty without reference columns
};

// Reads the columns of sim/io/columns.h (time, head, yaw, tips, references,
// measured deflections or joint references). Throws InputError naming the
// file for a table without rows or without a needed column.
BodyRecord ReadBodyRecord(const CsvTable& timeseries);

}  // namespace ipmc
