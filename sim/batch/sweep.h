// Parameter sweeps: the sweep file (sim/batch/sweep_file.h), running its
// points (sim/batch/sweep_scheduler.h) and the table of results
// (sim/batch/sweep_table.h); a scenario with overrides is
// sim/core/scenario_overrides.h.
#pragma once

#include "sim/batch/sweep_file.h"
#include "sim/batch/sweep_scheduler.h"
#include "sim/batch/sweep_table.h"
#include "sim/core/scenario_overrides.h"
