// Axis labels of the program's CSV columns: one table of column names with
// their words and units (sim/io/columns.h names the columns).
#pragma once

#include <string>

namespace ipmc {

// The axis label, with its unit, of a column of the program's CSV files
// ("mean_speed_along_mm_s" -> "mean speed along the swimming axis
// [mm/s]"); an array element "NAME[i]" of a sweep table too. Columns not
// in the table are spelled out from their name and unit suffix.
std::string AxisLabel(const std::string& column);

}  // namespace ipmc
